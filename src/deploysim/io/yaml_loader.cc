// LoadProfile, ApplyOverrides and the run-setting rules (docs/file_formats.md,
// "Deployment profiles"). LoadModel is in yaml_model.cc.

#include "deploysim/io/yaml_loader.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/io/yaml_fields.h"
#include "deploysim/math/quaternion.h"

namespace deploysim::io {

namespace {

using internal::Fields;
using internal::FormatNumber;
using internal::YamlDocument;

constexpr schedule::Mode kModes[] = {schedule::Mode::kTensor, schedule::Mode::kGeometry};
constexpr schedule::Coupling kCouplings[] = {schedule::Coupling::kQuasiRigid,
                                             schedule::Coupling::kExact};
constexpr schedule::Law kLaws[] = {schedule::Law::kStep, schedule::Law::kLinear,
                                   schedule::Law::kSmoothstep, schedule::Law::kMinimumJerk};

/// The value of `names` whose schedule::ToString is `name`, if any.
template <typename Enum, std::size_t N>
std::optional<Enum> FindByName(const Enum (&values)[N], const std::string& name) {
  for (Enum v : values) {
    if (schedule::ToString(v) == name) return v;
  }
  return std::nullopt;
}

template <typename Enum, std::size_t N>
std::string Names(const Enum (&values)[N]) {
  std::string s;
  for (Enum v : values) s += (s.empty() ? "" : ", ") + schedule::ToString(v);
  return s;
}

std::string Join(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

std::string Where(const schedule::Profile& p) {
  return p.source.empty() ? "profile '" + p.name + "'" : p.source;
}

/// The model file named by `model:`, relative to the profile's directory.
std::string ModelPath(const Fields& top) {
  const std::string relative = top.Text("model");
  if (relative.empty()) top.Fail("model", "must name a model file");
  const std::filesystem::path resolved =
      (std::filesystem::path(top.doc().path()).parent_path() / relative).lexically_normal();
  std::error_code ec;
  const bool is_dir = std::filesystem::is_directory(resolved, ec);
  std::ifstream probe(resolved);
  if (is_dir || !probe) {
    throw std::runtime_error(top.doc().path() + ": model = " + relative + ": cannot read " +
                             resolved.string() + ": " +
                             (is_dir ? std::string("is a directory") : std::strerror(errno)));
  }
  return resolved.string();
}

schedule::Mode ReadMode(const Fields& top, const model::Model& m) {
  if (!top.Has("mode")) {
    // Defaulted only where there is no choice: a tensor model has no geometry.
    if (m.kind == model::ModelKind::kTensors) return schedule::Mode::kTensor;
    top.doc().Fail("mode", "required key is missing (model '" + m.name + "' is hinged: choose " +
                               Names(kModes) + ")");
  }
  const std::optional<schedule::Mode> mode = FindByName(kModes, top.Text("mode"));
  if (!mode) top.Fail("mode", "unknown mode (valid: " + Names(kModes) + ")");
  return *mode;
}

schedule::Coupling ReadCoupling(const Fields& top, schedule::Mode mode) {
  if (!top.Has("coupling")) {
    // Tensor mode has no hinge rates: quasi-rigid is the only possibility.
    if (mode == schedule::Mode::kTensor) return schedule::Coupling::kQuasiRigid;
    top.doc().Fail("coupling",
                   "required key is missing in geometry mode (choose " + Names(kCouplings) + ")");
  }
  const std::optional<schedule::Coupling> c = FindByName(kCouplings, top.Text("coupling"));
  if (!c) top.Fail("coupling", "unknown coupling (valid: " + Names(kCouplings) + ")");
  return *c;
}

schedule::InitialState ReadInitial(const Fields& top) {
  const Fields f =
      top.Mapping("initial", {"attitude_wxyz", "angular_velocity", "angular_momentum"});
  schedule::InitialState init;
  if (f.Has("attitude_wxyz")) {
    const Eigen::VectorXd v = f.Numbers("attitude_wxyz", 4);
    const math::Vec4 wxyz(v[0], v[1], v[2], v[3]);
    const double norm = wxyz.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) {
      f.Fail("attitude_wxyz", "must be a non-zero quaternion (it is normalized on load)");
    }
    init.q_NB = math::FromWxyz(wxyz / norm);
  }
  f.RequireExactlyOne("angular_velocity", "angular_momentum");
  if (f.Has("angular_velocity")) {
    init.w_NB_B = f.Vector3("angular_velocity");
  } else {
    init.H_B = f.Vector3("angular_momentum");
  }
  return init;
}

std::vector<schedule::Stage> ReadStages(const Fields& top) {
  const YAML::Node& node = top.Get("stages");
  const std::vector<YAML::Node> nodes =
      internal::SequenceElements(top.doc(), node, "stages", "stages");
  if (nodes.empty()) top.Fail("stages", "at least one stage is required");
  std::vector<schedule::Stage> stages;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const Fields f(top.doc(), nodes[i], "stages[" + std::to_string(i) + "]",
                   {"name", "hold", "to", "law", "until", "start"});
    schedule::Stage s;
    if (f.Has("start") && i > 0) {
      f.Fail("start", "only the first stage may give start (stages are contiguous)");
    }
    s.t_begin = i == 0 ? f.OptionalNumber("start").value_or(0.0) : stages.back().t_end;
    s.t_end = f.Number("until");
    f.RequireExactlyOne("hold", "to");
    if (f.Has("hold")) {
      if (f.Has("law")) f.Fail("law", "a hold has no law (law is for `to` stages)");
      s.from = s.to = f.Text("hold");
      // The law of a hold is never used; keep the header's default.
    } else {
      if (i == 0) {
        f.Fail("to",
               "the first stage has no previous configuration to move from "
               "(start with a hold)");
      }
      s.to = f.Text("to");
      s.from = stages.back().to;
      const std::string law = f.Text("law");
      const std::optional<schedule::Law> l = FindByName(kLaws, law);
      if (!l) f.Fail("law", "unknown law (valid: " + Names(kLaws) + ")");
      s.law = *l;
    }
    s.name = f.OptionalText("name").value_or((s.is_hold() ? "hold " : "to ") + s.to);
    stages.push_back(s);
  }
  return stages;
}

schedule::IntegratorSpec ReadIntegrator(const Fields& top) {
  schedule::IntegratorSpec spec;
  if (!top.Has("integrator")) return spec;
  const Fields f = top.Mapping("integrator", {"method", "rtol", "atol", "step", "max_step"});
  spec.method = f.OptionalText("method").value_or(spec.method);
  spec.rtol = f.OptionalNumber("rtol").value_or(spec.rtol);
  spec.atol = f.OptionalNumber("atol").value_or(spec.atol);
  spec.step = f.OptionalNumber("step").value_or(spec.step);
  spec.max_step = f.OptionalNumber("max_step").value_or(spec.max_step);
  return spec;
}

schedule::OutputSpec ReadOutput(const Fields& top) {
  schedule::OutputSpec spec;
  if (!top.Has("output")) return spec;
  const Fields f = top.Mapping("output", {"dt", "csv"});
  spec.dt = f.OptionalNumber("dt").value_or(spec.dt);
  spec.csv = f.OptionalBool("csv").value_or(spec.csv);
  return spec;
}

void Validate(const schedule::Profile& p) {
  schedule::ValidateProfile(p);
  CheckRunSettings(p);
}

}  // namespace

schedule::Mode ParseMode(const std::string& name) {
  const std::optional<schedule::Mode> m = FindByName(kModes, name);
  if (!m) throw std::invalid_argument(name + ": unknown mode (valid: " + Names(kModes) + ")");
  return *m;
}

schedule::Coupling ParseCoupling(const std::string& name) {
  const std::optional<schedule::Coupling> c = FindByName(kCouplings, name);
  if (!c) {
    throw std::invalid_argument(name + ": unknown coupling (valid: " + Names(kCouplings) + ")");
  }
  return *c;
}

void CheckRunSettings(const schedule::Profile& p) {
  const std::string where = Where(p);
  const std::string& method = p.integrator.method;
  const std::vector<std::string> names = analysis::StepperNames();
  bool known = false;
  for (const std::string& n : names) known = known || n == method;
  if (!known) {
    throw std::invalid_argument(where + ": integrator.method = " + method +
                                ": unknown integrator (valid: " + Join(names) + ")");
  }
  if (!analysis::MakeStepper(method)->info().adaptive && !(p.integrator.step > 0.0)) {
    throw std::invalid_argument(where + ": integrator.step = " + FormatNumber(p.integrator.step) +
                                ": the fixed-step method " + method +
                                " needs integrator.step > 0 [s]");
  }
  if (!p.stages.empty() && p.output.dt > 0.0) {
    const double samples = (p.t_end() - p.t_begin()) / p.output.dt + 1.0;
    if (!(samples <= kMaxOutputSamples)) {
      throw std::invalid_argument(where + ": output.dt = " + FormatNumber(p.output.dt) +
                                  ": gives " + FormatNumber(std::ceil(samples)) +
                                  " output samples over " + FormatNumber(p.t_end() - p.t_begin()) +
                                  " s (at most " + FormatNumber(kMaxOutputSamples) + ")");
    }
  }
}

schedule::Profile LoadProfile(const std::string& path) {
  const YamlDocument doc(path, internal::ReadTextFile(path));
  const Fields top(doc, doc.root(), "",
                   {"name", "description", "model", "mode", "coupling", "initial", "stages",
                    "integrator", "output"});
  schedule::Profile p;
  p.source = path;
  p.text = doc.text();
  p.name = top.Text("name");
  if (p.name.empty()) top.Fail("name", "must not be empty");
  p.description = top.OptionalText("description").value_or("");
  p.model = LoadModel(ModelPath(top));
  p.mode = ReadMode(top, p.model);
  p.coupling = ReadCoupling(top, p.mode);
  p.initial = ReadInitial(top);
  p.stages = ReadStages(top);
  p.integrator = ReadIntegrator(top);
  p.output = ReadOutput(top);
  Validate(p);
  return p;
}

void ApplyOverrides(schedule::Profile& profile, const ProfileOverrides& o) {
  const std::string where = Where(profile);
  schedule::Profile p = profile;
  if (o.method) p.integrator.method = *o.method;
  if (o.rtol) p.integrator.rtol = *o.rtol;
  if (o.atol) p.integrator.atol = *o.atol;
  if (o.step) p.integrator.step = *o.step;
  if (o.output_dt) p.output.dt = *o.output_dt;
  if (o.mode) {
    const std::optional<schedule::Mode> m = FindByName(kModes, *o.mode);
    if (!m) {
      throw std::invalid_argument(where + ": mode = " + *o.mode +
                                  " (override): unknown mode (valid: " + Names(kModes) + ")");
    }
    p.mode = *m;
  }
  if (o.coupling) {
    const std::optional<schedule::Coupling> c = FindByName(kCouplings, *o.coupling);
    if (!c) {
      throw std::invalid_argument(where + ": coupling = " + *o.coupling +
                                  " (override): unknown coupling (valid: " + Names(kCouplings) +
                                  ")");
    }
    p.coupling = *c;
  }
  Validate(p);
  profile = std::move(p);
}

}  // namespace deploysim::io
