// ReadProfile and the mode / coupling names (docs/file_formats.md, "Deployment
// profiles"). LoadModel is in yaml_model.cc; the run-setting rules that need the
// integrators (io::LoadProfile, CheckRunSettings) are in yaml_loader.cc (deploysim::io).

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/io/yaml_fields.h"
#include "deploysim/io/yaml_reader.h"
#include "deploysim/math/quaternion.h"

namespace deploysim::io {

namespace {

using yaml::Fields;
using yaml::YamlDocument;
using yaml::YamlNode;

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

schedule::Mode ReadMode(const Fields& top, const model::Model& m) {
  if (!top.Has("mode")) {
    // Defaulted only where there is no choice: a tensor model has no geometry.
    if (m.kind == model::ModelKind::kTensors) return schedule::Mode::kTensor;
    top.doc().Fail("mode", "required key is missing (model '" + yaml::ShortValue(m.name) +
                               "' is hinged: choose " + Names(kModes) + ")");
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

/// Refuses a `hold` / `to` that names no configuration of the model, with a bounded
/// message (schedule::ValidateProfile would list every configuration).
void RequireConfiguration(const Fields& f, const std::string& key, const model::Model& m) {
  const std::string name = f.Text(key);
  std::vector<std::string> names;
  for (const model::Configuration& c : m.configurations) {
    if (c.name == name) return;
    names.push_back(c.name);
  }
  f.doc().Fail(f.Key(key) + " = '" + yaml::ShortValue(name) + "'",
               "no configuration of that name in model '" + yaml::ShortValue(m.name) +
                   "' (valid: " + yaml::ShortList(names) + ")");
}

std::vector<schedule::Stage> ReadStages(const Fields& top, const model::Model& m) {
  const std::vector<YamlNode> nodes =
      yaml::SequenceElements(top.doc(), top.Get("stages"), "stages", "stages");
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
      s.from = s.to = f.Name("hold");
      RequireConfiguration(f, "hold", m);
      // The law of a hold is never used; keep the header's default.
    } else {
      if (i == 0) {
        f.Fail("to",
               "the first stage has no previous configuration to move from "
               "(start with a hold)");
      }
      s.to = f.Name("to");
      RequireConfiguration(f, "to", m);
      s.from = stages.back().to;
      const std::string law = f.Text("law");
      const std::optional<schedule::Law> l = FindByName(kLaws, law);
      if (!l) f.Fail("law", "unknown law (valid: " + Names(kLaws) + ")");
      s.law = *l;
    }
    if (f.Has("name")) {
      s.name = f.Text("name");
      if (!s.name.empty()) (void)f.Name("name");  // the name rules (empty: allowed here)
    } else {
      s.name = (s.is_hold() ? "hold " : "to ") + s.to;
    }
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

schedule::Profile ReadProfile(const std::string& path) {
  const YamlDocument doc(path, yaml::ReadTextFile(path));
  const Fields top(doc, doc.root(), "",
                   {"name", "description", "model", "mode", "coupling", "initial", "stages",
                    "integrator", "output"});
  schedule::Profile p;
  p.source = path;
  p.text = doc.text();
  p.name = top.Name("name");
  p.description = top.OptionalText("description").value_or("");
  p.model = LoadModel(top.FilePath("model"));
  p.mode = ReadMode(top, p.model);
  p.coupling = ReadCoupling(top, p.mode);
  p.initial = ReadInitial(top);
  p.stages = ReadStages(top, p.model);
  p.integrator = ReadIntegrator(top);
  p.output = ReadOutput(top);
  schedule::ValidateProfile(p);
  return p;
}

std::optional<schedule::Mode> FindMode(const std::string& name) { return FindByName(kModes, name); }

std::optional<schedule::Coupling> FindCoupling(const std::string& name) {
  return FindByName(kCouplings, name);
}

std::string ModeNames() { return Names(kModes); }

std::string CouplingNames() { return Names(kCouplings); }

}  // namespace deploysim::io
