// ReadProfile and the mode / coupling names (docs/file_formats.md, "Deployment
// profiles" and "Hinge profiles"). LoadModel is in yaml_model.cc; the run-setting rules
// that need the integrators (io::LoadProfile, CheckRunSettings) are in yaml_loader.cc
// (deploysim::io).

#include "deploysim/io/yaml_profile.h"

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/io/yaml_fields.h"
#include "deploysim/io/yaml_reader.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/schedule/initial_spin.h"

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

/// Refuses a `hold` / `to` / `configuration` that names no configuration of the model, with
/// a bounded message (schedule::ValidateProfile would list every configuration).
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

/// A body axis: `x`, `y`, `z` (optionally signed: `-y`) or three components.
math::Vec3 ReadAxis(const Fields& f, const std::string& key) {
  const std::string name = f.Get(key).Scalar();
  if (name.empty()) {
    const math::Vec3 v = f.Vector3(key);
    if (!(v.norm() > 0.0)) f.Fail(key, "must be a non-zero vector (it is normalized on load)");
    return v.normalized();
  }
  static const std::vector<std::pair<std::string, math::Vec3>> kAxes = {
      {"x", math::Vec3::UnitX()},   {"y", math::Vec3::UnitY()},   {"z", math::Vec3::UnitZ()},
      {"+x", math::Vec3::UnitX()},  {"+y", math::Vec3::UnitY()},  {"+z", math::Vec3::UnitZ()},
      {"-x", -math::Vec3::UnitX()}, {"-y", -math::Vec3::UnitY()}, {"-z", -math::Vec3::UnitZ()}};
  for (const auto& [n, v] : kAxes) {
    if (n == name) return v;
  }
  f.Fail(key, "unknown axis (valid: x, y, z, -x, -y, -z, or [x, y, z] in body components)");
}

/// `initial.spin`: a spin rate about a body axis with a nutation (schedule/initial_spin.h).
schedule::InitialSpin ReadSpin(const Fields& initial) {
  const Fields f = initial.Mapping(
      "spin", {"axis", "rate_rpm", "rate_deg_s", "rate", "nutation_deg", "nutation_azimuth_deg"});
  schedule::InitialSpin spin;
  spin.axis_B = ReadAxis(f, "axis");
  const std::string rate_key = f.RequireExactlyOne({"rate_rpm", "rate_deg_s", "rate"});
  const double factor = rate_key == "rate_rpm"     ? yaml::kRadPerSecondPerRpm
                        : rate_key == "rate_deg_s" ? yaml::kRadiansPerDegree
                                                   : 1.0;
  spin.rate = f.Number(rate_key) * factor;
  spin.rate_in_rpm = rate_key == "rate_rpm";
  if (!(spin.rate > 0.0)) f.Fail(rate_key, "must be > 0 (the axis gives the direction)");
  spin.nutation = f.OptionalDegrees("nutation_deg");
  if (spin.nutation && !(*spin.nutation >= 0.0 && *spin.nutation < 0.5 * 3.14159265358979323846)) {
    f.Fail("nutation_deg", "must be in [0, 90) deg");
  }
  spin.azimuth = f.OptionalDegrees("nutation_azimuth_deg");
  return spin;
}

/// The one initial rotation state: angular velocity (in rad/s, deg/s or rpm), angular
/// momentum, or a spin about an axis.
void ReadRotation(const Fields& f, schedule::InitialState& init) {
  const std::string key = f.RequireExactlyOne({"angular_velocity", "angular_velocity_deg_s",
                                               "angular_velocity_rpm", "angular_momentum", "spin"});
  if (key == "angular_momentum") {
    init.H_B = f.Vector3(key);
  } else if (key == "spin") {
    init.spin = ReadSpin(f);
  } else {
    const double factor = key == "angular_velocity_deg_s" ? yaml::kRadiansPerDegree
                          : key == "angular_velocity_rpm" ? yaml::kRadPerSecondPerRpm
                                                          : 1.0;
    init.w_NB_B = f.Vector3(key) * factor;
  }
}

schedule::InitialState ReadInitial(const Fields& top, bool hinge_profile, const model::Model& m) {
  const Fields f =
      top.Mapping("initial", {"attitude_wxyz", "angular_velocity", "angular_velocity_deg_s",
                              "angular_velocity_rpm", "angular_momentum", "spin", "configuration",
                              "hinge_rates_deg_s"});
  schedule::InitialState init;
  if (hinge_profile) {
    init.configuration = f.Name("configuration");
    RequireConfiguration(f, "configuration", m);
    if (f.Has("hinge_rates_deg_s")) {
      // The count is checked (with the rule) by schedule::ValidateProfile.
      init.hinge_rates = f.Numbers("hinge_rates_deg_s", -1) * yaml::kRadiansPerDegree;
    }
  } else if (f.Has("hinge_rates_deg_s")) {
    f.Fail("hinge_rates_deg_s", "only in hinge profiles (`hinges:`)");
  } else if (f.Has("configuration")) {
    f.Fail("configuration",
           "only in hinge profiles (`hinges:`): a stage profile starts in the configuration "
           "of its first stage");
  }
  if (f.Has("attitude_wxyz")) {
    const Eigen::VectorXd v = f.Numbers("attitude_wxyz", 4);
    const math::Vec4 wxyz(v[0], v[1], v[2], v[3]);
    const double norm = wxyz.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) {
      f.Fail("attitude_wxyz", "must be a non-zero quaternion (it is normalized on load)");
    }
    init.q_NB = math::FromWxyz(wxyz / norm);
  }
  ReadRotation(f, init);
  return init;
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

// --- Hinge profiles (`hinges:`, docs/file_formats.md "Hinge profiles") ---------------------
// The reader checks structure, types, finiteness and names (panel names resolve to
// indices); ranges and cross-field rules are schedule::ValidateProfile's.

/// The index of the panel called `name`, or -1.
int FindPanel(const model::Model& m, const std::string& name) {
  for (std::size_t k = 0; k < m.hinged.panels.size(); ++k) {
    if (m.hinged.panels[k].name == name) return static_cast<int>(k);
  }
  return -1;
}

std::string PanelNames(const model::Model& m) {
  std::vector<std::string> names;
  for (const model::Panel& pn : m.hinged.panels) names.push_back(pn.name);
  return yaml::ShortList(names);
}

std::string NoSuchPanel(const model::Model& m) {
  return "no panel of that name in model '" + yaml::ShortValue(m.name) +
         "' (valid: " + PanelNames(m) + ")";
}

/// `mode` and `coupling` of a hinge profile: optional, and only geometry / exact.
void ReadHingeModes(const Fields& top, schedule::Profile& p) {
  p.mode = schedule::Mode::kGeometry;
  p.coupling = schedule::Coupling::kExact;
  if (top.Has("mode") && top.Text("mode") != schedule::ToString(p.mode)) {
    top.Fail("mode",
             "a hinge profile runs in geometry mode (the hinge angles are the state): "
             "mode geometry, or leave mode out");
  }
  if (top.Has("coupling") && top.Text("coupling") != schedule::ToString(p.coupling)) {
    top.Fail("coupling",
             "a hinge profile runs with exact coupling (the hinge rates enter the momentum): "
             "coupling exact, or leave coupling out");
  }
}

schedule::Release ReadRelease(const Fields& f, const model::Model& m) {
  schedule::Release r;
  f.RequireExactlyOne("at", "after_latch");
  if (f.Has("at")) {
    if (f.Has("delay")) {
      f.Fail("delay", "delay goes with after_latch (`at` is the release time itself)");
    }
    r.kind = schedule::Release::Kind::kAtTime;
    r.time = f.Number("at");
  } else {
    r.kind = schedule::Release::Kind::kAfterLatch;
    r.panel = FindPanel(m, f.Name("after_latch"));
    if (r.panel < 0) f.Fail("after_latch", NoSuchPanel(m));
    r.delay = f.OptionalNumber("delay").value_or(0.0);
  }
  return r;
}

std::vector<schedule::HingeMove> ReadMoves(const Fields& plan, const std::string& name);

schedule::Motor ReadMotor(const Fields& f) {
  schedule::Motor motor;
  if (f.Has("servo_stiffness") || f.Has("servo_damping") || f.Has("follow")) {
    for (const char* key : {"torque", "stall_torque", "no_load_speed_deg_s"}) {
      if (f.Has(key)) {
        f.Fail(key,
               "a servo motor (servo_stiffness, servo_damping, follow) has no constant torque "
               "or torque-speed line");
      }
    }
    motor.kind = schedule::Motor::Kind::kServo;
    motor.servo_stiffness = f.Number("servo_stiffness");
    motor.servo_damping = f.OptionalNumber("servo_damping").value_or(0.0);
    motor.follow = ReadMoves(f, "follow");
    return motor;
  }
  if (f.Has("torque")) {
    for (const char* key : {"stall_torque", "no_load_speed_deg_s"}) {
      if (f.Has(key)) {
        f.Fail(key,
               "a motor gives either torque (constant) or stall_torque and "
               "no_load_speed_deg_s (a torque-speed line), not both");
      }
    }
    motor.kind = schedule::Motor::Kind::kConstant;
    motor.torque = f.Number("torque");
    return motor;
  }
  if (!f.Has("stall_torque") && !f.Has("no_load_speed_deg_s")) {
    f.doc().Fail(f.path(), f.node(),
                 "a motor needs torque (constant, N m), or stall_torque (N m) and "
                 "no_load_speed_deg_s (a torque-speed line)");
  }
  motor.kind = schedule::Motor::Kind::kTorqueSpeed;
  motor.stall_torque = f.Number("stall_torque");
  motor.no_load_speed = f.Degrees("no_load_speed_deg_s");
  return motor;
}

schedule::FreeDrive ReadFreeDrive(const Fields& f, const model::Model& m) {
  schedule::FreeDrive d;
  if (f.Has("release"))
    d.release = ReadRelease(f.Mapping("release", {"at", "after_latch", "delay"}), m);
  if (f.Has("spring")) {
    const Fields s = f.Mapping("spring", {"stiffness", "rest_angle_deg", "preload"});
    d.spring.stiffness = s.Number("stiffness");
    d.spring.rest_angle = s.Degrees("rest_angle_deg");
    d.spring.preload = s.OptionalNumber("preload").value_or(0.0);
  }
  if (f.Has("damper")) d.damping = f.Mapping("damper", {"coefficient"}).Number("coefficient");
  if (f.Has("motor")) {
    d.motor = ReadMotor(f.Mapping("motor", {"torque", "stall_torque", "no_load_speed_deg_s",
                                            "servo_stiffness", "servo_damping", "follow"}));
  }
  if (f.Has("friction")) {
    const Fields fr = f.Mapping("friction", {"torque", "regularization_speed_deg_s"});
    d.friction.torque = fr.Number("torque");
    // Left out: exact Coulomb friction (sticks and slips; schedule::Friction).
    d.friction.regularization_speed =
        fr.OptionalDegrees("regularization_speed_deg_s").value_or(0.0);
  }
  if (f.Has("stops")) {
    const Fields st = f.Mapping("stops", {"min_deg", "max_deg", "restitution"});
    d.stops.min_angle = st.OptionalDegrees("min_deg").value_or(d.stops.min_angle);
    d.stops.max_angle = st.OptionalDegrees("max_deg").value_or(d.stops.max_angle);
    d.stops.restitution = st.OptionalNumber("restitution").value_or(0.0);
  }
  if (f.Has("latch")) {
    const Fields l = f.Mapping("latch", {"angle_deg", "jam_fraction"});
    d.latch.enabled = true;
    d.latch.angle = l.Degrees("angle_deg");
    d.latch.jam_fraction = l.OptionalNumber("jam_fraction").value_or(0.0);
  }
  return d;
}

/// The moves under `name` (a prescribed plan's `prescribed`, a servo motor's `follow`).
std::vector<schedule::HingeMove> ReadMoves(const Fields& plan, const std::string& name) {
  const std::string key = plan.Key(name);
  const std::vector<YamlNode> nodes =
      yaml::SequenceElements(plan.doc(), plan.Get(name), key, "moves");
  if (nodes.empty()) {
    plan.Fail(name,
              "at least one move is required (a hinge that does not move: locked: true, or "
              "leave the panel out)");
  }
  std::vector<schedule::HingeMove> moves;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const Fields f(plan.doc(), nodes[i], key + "[" + std::to_string(i) + "]",
                   {"to_deg", "rate_deg_s", "law", "start", "until"});
    schedule::HingeMove mv;
    f.RequireExactlyOne("to_deg", "rate_deg_s");
    if (f.Has("to_deg")) {
      mv.kind = schedule::HingeMove::Kind::kTo;
      mv.angle = f.Degrees("to_deg");
      const std::optional<schedule::Law> law = FindByName(kLaws, f.Text("law"));
      if (!law) f.Fail("law", "unknown law (valid: " + Names(kLaws) + ")");
      mv.law = *law;
    } else {
      mv.kind = schedule::HingeMove::Kind::kRate;
      if (f.Has("law")) f.Fail("law", "a rate move has no law (law is for to_deg moves)");
      mv.rate = f.Degrees("rate_deg_s");
    }
    mv.t_begin = f.Number("start");
    mv.t_end = f.Number("until");
    moves.push_back(mv);
  }
  return moves;
}

/// The appendage whose bending hinge panel k is, or null.
const model::Appendage* BendingHingeOf(const model::Model& m, int k) {
  for (const model::Appendage& a : m.appendages) {
    for (int h : a.hinges) {
      if (h == k) return &a;
    }
  }
  return nullptr;
}

/// One plan per panel, in panel order; panels not listed are locked.
std::vector<schedule::HingePlan> ReadHinges(const Fields& top, const model::Model& m) {
  const YamlDocument& doc = top.doc();
  std::vector<schedule::HingePlan> plans(m.hinged.panels.size());
  for (const auto& [name, node] : yaml::MappingEntries(doc, top.Get("hinges"), "hinges")) {
    const std::string key = yaml::JoinKey("hinges", name);
    const int k = FindPanel(m, name);
    if (k < 0) doc.Fail(key, node, NoSuchPanel(m));
    if (const model::Appendage* a = BendingHingeOf(m, k)) {
      doc.Fail(key, node,
               "a bending hinge of appendage " + a->name +
                   ": its spring and damper come from the model's EI and damping_ratio (rule: "
                   "a profile moves an appendage by its root hinge, " +
                   a->name + ")");
    }
    const Fields f(doc, node, key, {"free", "prescribed", "locked"});
    const int given = int{f.Has("free")} + int{f.Has("prescribed")} + int{f.Has("locked")};
    if (given != 1) {
      doc.Fail(key, node,
               "exactly one of free, prescribed, locked is required (" +
                   std::string(given == 0 ? "none is" : "several are") + " given)");
    }
    schedule::HingePlan& plan = plans[static_cast<std::size_t>(k)];
    if (f.Has("free")) {
      plan.kind = schedule::HingePlan::Kind::kFree;
      plan.drive = ReadFreeDrive(
          f.Mapping("free", {"release", "spring", "damper", "motor", "friction", "stops", "latch"}),
          m);
    } else if (f.Has("prescribed")) {
      plan.kind = schedule::HingePlan::Kind::kPrescribed;
      plan.moves = ReadMoves(f, "prescribed");
    } else {
      plan.kind = schedule::HingePlan::Kind::kLocked;
      if (!*f.OptionalBool("locked")) {
        f.Fail("locked",
               "must be true (a panel left out of hinges is locked too; to move it, give free "
               "or prescribed)");
      }
    }
  }
  schedule::SetAppendagePlans(m, plans);
  return plans;
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
  const std::string text = yaml::ReadTextFile(path);
  return ReadProfileText(text, path, std::filesystem::path(path).parent_path().string());
}

schedule::Profile ParseProfile(const std::string& path) {
  const std::string text = yaml::ReadTextFile(path);
  return ParseProfileText(text, path, std::filesystem::path(path).parent_path().string());
}

schedule::Profile ReadProfileText(const std::string& text,
                                  const std::string& source,
                                  const std::string& base_dir,
                                  const model::Model* model) {
  schedule::Profile p = ParseProfileText(text, source, base_dir, model);
  schedule::ValidateProfile(p);
  if (p.initial.spin) {
    // J_B(t0) needs the validated model and plans.
    p.initial.H_B = schedule::SpinMomentum(schedule::InitialInertia(p), *p.initial.spin);
  }
  return p;
}

schedule::Profile ParseProfileText(const std::string& text,
                                   const std::string& source,
                                   const std::string& base_dir,
                                   const model::Model* model) {
  const std::string& path = source;
  const YamlDocument doc(source, text, base_dir);
  const Fields top(
      doc, doc.root(), "",
      {"name", "description", "model", "mode", "coupling", "initial", "stages", "hinges", "start",
       "until", "integrator", "output", "base", "grid", "monte_carlo", "outcome"});
  if (top.Has("base")) {
    top.Fail("base",
             "this is a sweep file (it has base:), not a deployment profile: run it with "
             "`deploysim sweep " +
                 source + " -o RESULTS.h5` (docs/sweeps.md)");
  }
  for (const char* key : {"grid", "monte_carlo", "outcome"}) {
    if (top.Has(key)) top.Fail(key, "unknown key (a key of sweep files, docs/sweeps.md)");
  }
  schedule::Profile p;
  p.source = path;
  p.text = doc.text();
  p.name = top.Name("name");
  p.description = top.OptionalText("description").value_or("");
  // A stage profile moves every panel through the stages' configurations together; a hinge
  // profile gives each panel its own plan.
  if (top.Has("stages") && top.Has("hinges")) {
    top.Fail("hinges",
             "a profile has either stages (every panel through the stages' configurations) "
             "or hinges (a plan per panel), not both");
  }
  const bool hinge_profile = top.Has("hinges");
  if (!hinge_profile) {
    if (!top.Has("stages")) {
      doc.Fail("stages",
               "required key is missing (a profile has stages, or hinges for a plan per "
               "panel)");
    }
    for (const char* key : {"start", "until"}) {
      if (top.Has(key)) {
        top.Fail(key,
                 "top-level start and until are keys of hinge profiles (`hinges:`); a stage "
                 "profile gives start on its first stage and until on every stage");
      }
    }
  }
  if (model != nullptr) {
    (void)top.Text("model");  // still required, and a string: the model's name or file
    p.model = *model;
  } else {
    p.model = LoadModel(top.FilePath("model"));
  }
  if (hinge_profile) {
    if (p.model.kind != model::ModelKind::kHinged) {
      top.Fail("model", "hinges need a hinged model (model '" + yaml::ShortValue(p.model.name) +
                            "' is kind tensors)");
    }
    ReadHingeModes(top, p);
    p.initial = ReadInitial(top, true, p.model);
    p.start = top.OptionalNumber("start").value_or(0.0);
    p.until = top.Number("until");
    p.hinges = ReadHinges(top, p.model);
  } else {
    if (!p.model.appendages.empty()) {
      top.Fail("stages",
               "model '" + yaml::ShortValue(p.model.name) + "' has a flexible appendage (" +
                   p.model.appendages.front().name +
                   "), whose bending needs the free-hinge dynamics: give hinges, not stages");
    }
    p.mode = ReadMode(top, p.model);
    p.coupling = ReadCoupling(top, p.mode);
    p.initial = ReadInitial(top, false, p.model);
    p.stages = ReadStages(top, p.model);
  }
  p.integrator = ReadIntegrator(top);
  p.output = ReadOutput(top);
  return p;
}

std::optional<schedule::Mode> FindMode(const std::string& name) { return FindByName(kModes, name); }

std::optional<schedule::Coupling> FindCoupling(const std::string& name) {
  return FindByName(kCouplings, name);
}

std::string ModeNames() { return Names(kModes); }

std::string CouplingNames() { return Names(kCouplings); }

}  // namespace deploysim::io
