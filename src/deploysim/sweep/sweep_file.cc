// LoadSweep: sweep files (docs/sweeps.md) with io's strict YAML reader (io/yaml_fields.h,
// which keeps yaml-cpp inside io).

#include "deploysim/sweep/sweep_file.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/io/yaml_fields.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/math/number_format.h"
#include "deploysim/sweep/parallel.h"

namespace deploysim::sweep {

namespace {

using io::yaml::Fields;
using io::yaml::YamlDocument;
using io::yaml::YamlNode;
using math::FormatNumber;

constexpr double kDegree = io::yaml::kRadiansPerDegree;  // [rad]
constexpr double kRpm = io::yaml::kRadPerSecondPerRpm;   // [rad/s]
constexpr double kMaxAxisValues = 1e6;                   // values per grid axis
constexpr double kMaxSeed = 9007199254740992.0;          // 2^53: exact in a double

/// How a parameter is written in a file.
struct ParameterInfo {
  const char* name;  ///< Key in files (`parameter: ...`).
  Parameter parameter;
  const char* column;  ///< Column base name.
  double to_si;        ///< File value * to_si = SI value.
  double lower;        ///< Valid range [lower, upper) or (lower, upper) in file units.
  bool lower_open;     ///< true: value > lower; false: value >= lower.
  double upper;        ///< value < upper (+inf: unbounded).
  /// Units of the value in files, for messages ("": none); nullptr: not a number (a
  /// choice of names), no range.
  const char* unit;
  const char* description;
  bool upper_closed = false;  ///< true: value <= upper (fill_fraction).
  const char* note = "";      ///< said after the range in messages ("0: no jam")
};

/// The bounds of a message: the shortest text that reads back ("1e9", not "1e+09").
std::string Bound(double x) {
  std::string s = FormatNumber(x);
  const std::size_t e = s.find('e');
  if (e == std::string::npos) return s;
  std::string exponent = s.substr(e + 1);
  const bool negative = exponent[0] == '-';
  if (exponent[0] == '+' || negative) exponent.erase(0, 1);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return s.substr(0, e + 1) + (negative ? "-" : "") + exponent;
}

/// The accepted range of a parameter as messages state it, from its bounds ("must be > 0
/// [s]", "must be in [0, 1e9] [N m/rad]", "must be finite [deg]").
std::string RangeRule(const ParameterInfo& p) {
  std::string rule;
  if (std::isinf(p.lower) && std::isinf(p.upper)) {
    rule = "must be finite";
  } else if (std::isinf(p.upper)) {
    rule = std::string(p.lower_open ? "must be > " : "must be >= ") + Bound(p.lower);
  } else {
    rule = std::string("must be in ") + (p.lower_open ? "(" : "[") + Bound(p.lower) + ", " +
           Bound(p.upper) + (p.upper_closed ? "]" : ")");
  }
  if (*p.unit != '\0') rule += std::string(" [") + p.unit + "]";
  if (*p.note != '\0') rule += std::string(" (") + p.note + ")";
  return rule;
}

const double kInf = std::numeric_limits<double>::infinity();

const ParameterInfo kParameters[] = {
    {"deploy_duration_scale", Parameter::kDeployDurationScale, "deploy_duration_scale", 1.0, 0.0,
     true, kInf, "", "factor on the duration of every move stage"},
    {"stage_duration", Parameter::kStageDuration, "stage_duration", 1.0, 0.0, true, kInf, "s",
     "duration of one stage [s]"},
    {"spin_rate", Parameter::kSpinRate, "spin_rate", 1.0, 0.0, true, kInf, "rad/s",
     "initial spin rate w_NB_B(t0) . s about the body spin axis s"},
    {"spin_rate_rpm", Parameter::kSpinRate, "spin_rate", kRpm, 0.0, true, kInf, "rpm",
     "initial spin rate w_NB_B(t0) . s about the body spin axis s"},
    {"nutation_deg", Parameter::kNutation, "nutation", kDegree, 0.0, false, 90.0, "deg",
     "initial angle between H_B and the body spin axis s"},
    {"nutation_azimuth_deg", Parameter::kNutationAzimuth, "nutation_azimuth", kDegree, -kInf, false,
     kInf, "deg", "direction of the initial tilt of H_B about s, from the base profile's tilt"},
    {"panel_mass_scale", Parameter::kPanelMassScale, "panel_mass_scale", 1.0, 0.0, true, kInf, "",
     "factor on panel mass and inertia"},
    {"inertia_scale", Parameter::kInertiaScale, "inertia_scale", 1.0, 0.0, true, kInf, "",
     "factor on configuration inertia tensors"},
    {"law", Parameter::kLaw, "law", 1.0, 0.0, false, kInf, nullptr,
     "interpolation law of move stages"},
    {"coupling", Parameter::kCoupling, "coupling", 1.0, 0.0, false, kInf, nullptr,
     "coupling of the panels' relative momentum"},
    // Free hinges (hinge profiles).
    {"spring_stiffness", Parameter::kSpringStiffness, "spring_stiffness", 1.0, 0.0, false,
     schedule::kMaxDriveStiffness, "N m/rad",
     "torsion spring stiffness of the free hinge [N m/rad]", true},
    {"spring_stiffness_scale", Parameter::kSpringStiffnessScale, "spring_stiffness_scale", 1.0, 0.0,
     false, kInf, "", "factor on the spring stiffness of the free hinge (< 1: a weak spring)"},
    {"damping", Parameter::kDamping, "damping", 1.0, 0.0, false, schedule::kMaxDriveDamping,
     "N m s/rad", "viscous damper coefficient of the free hinge [N m s/rad]", true},
    {"latch_angle_deg", Parameter::kLatchAngle, "latch_angle", kDegree,
     -schedule::kMaxDriveAngleDeg, false, schedule::kMaxDriveAngleDeg, "deg",
     "latch angle of the free hinge [rad]", true},
    {"motor_torque", Parameter::kMotorTorque, "motor_torque", 1.0, -schedule::kMaxDriveTorque,
     false, schedule::kMaxDriveTorque, "N m",
     "torque of a constant motor on the free hinge [N m] (> 0 turns towards increasing angle)",
     true},
    {"motor_torque_scale", Parameter::kMotorTorqueScale, "motor_torque_scale", 1.0, 0.0, true, kInf,
     "", "factor on the motor torque (constant motor) or stall torque (torque-speed motor)"},
    {"release_time", Parameter::kReleaseTime, "release_time", 1.0, -kInf, false, kInf, "s",
     "release time of the free hinge [s]"},
    {"release_delay", Parameter::kReleaseDelay, "release_delay", 1.0, 0.0, false, kInf, "s",
     "delay of the free hinge's release after the latch it waits for [s]"},
    {"friction_torque", Parameter::kFrictionTorque, "friction_torque", 1.0, 0.0, false,
     schedule::kMaxDriveTorque, "N m", "Coulomb friction torque of the free hinge [N m]", true},
    {"stick_fraction", Parameter::kStickFraction, "stick_fraction", 1.0, 0.0, false, 1.0, "",
     "fraction of the swing from release to latch at which the hinge jams (0: no jam)", false,
     "0: no jam"},
    {"latch_fails", Parameter::kLatchFails, "latch_fails", 1.0, 0.0, false, kInf, nullptr,
     "yes: the latch does not catch the panel (panels released after it never are)"},
    // The model's appendages.
    {"bending_stiffness", Parameter::kBendingStiffness, "bending_stiffness", 1.0, 0.0, true, kInf,
     "N m^2", "bending stiffness EI of every bending plane of the beam [N m^2]"},
    {"bending_stiffness_scale", Parameter::kBendingStiffnessScale, "bending_stiffness_scale", 1.0,
     0.0, true, kInf, "", "factor on the bending stiffness EI of every bending plane of the beam"},
    {"damping_ratio", Parameter::kDampingRatio, "damping_ratio", 1.0, 0.0, false, 1.0, "",
     "damping ratio of the appendage (a beam's first bending mode, a slosh pendulum's swing "
     "along the spin axis)"},
    {"fill_fraction", Parameter::kFillFraction, "fill_fraction", 1.0, 0.0, true, 1.0, "",
     "fill fraction of the slosh tank (share of its volume)", true},
};

std::string ParameterNames() {
  std::string s;
  for (const ParameterInfo& p : kParameters) s += (s.empty() ? "" : ", ") + std::string(p.name);
  return s;
}

/// Names for a message (bounded: io::yaml::ShortList).
std::string JoinNames(const std::vector<std::string>& v) { return io::yaml::ShortList(v); }

/// A name from an input file, for a message.
std::string Short(const std::string& s) { return io::yaml::ShortValue(s); }

/// One axis entry being read: its parameter, target and the valid range of its values
/// (the parameter's, or narrower where the base profile says so).
struct Entry {
  const ParameterInfo* info = nullptr;
  Target target;
  double lower = 0.0;
  bool lower_open = false;
  double upper = 0.0;
  bool upper_closed = false;
  std::string rule;

  bool InRange(double v) const {
    return (lower_open ? v > lower : v >= lower) && (upper_closed ? v <= upper : v < upper);
  }
};

/// Why a hinge parameter does not apply to a free hinge's drive, or "" when it does.
std::string NotApplicable(Parameter par,
                          const schedule::FreeDrive& d,
                          const schedule::Profile& base) {
  using schedule::Motor;
  using schedule::Release;
  const bool spring =
      d.spring.stiffness > 0.0 || d.spring.rest_angle != 0.0 || d.spring.preload != 0.0;
  switch (par) {
    case Parameter::kSpringStiffness:
      return spring ? "" : "has no spring (give it one, with its rest angle, in the base profile)";
    case Parameter::kSpringStiffnessScale:
      return d.spring.stiffness > 0.0 ? "" : "has no spring stiffness to scale (stiffness 0)";
    case Parameter::kLatchAngle:
    case Parameter::kLatchFails:
      return d.latch.enabled ? "" : "has no latch";
    case Parameter::kStickFraction:
      return d.latch.enabled ? ""
                             : "has no latch (a jam is a fraction of the swing to the latch angle)";
    case Parameter::kMotorTorque:
      return d.motor.kind != Motor::Kind::kTorqueSpeed
                 ? ""
                 : "has a torque-speed motor (vary it with motor_torque_scale)";
    case Parameter::kMotorTorqueScale:
      return d.motor.kind != Motor::Kind::kNone ? "" : "has no motor";
    case Parameter::kReleaseTime:
      if (d.release.kind != Release::Kind::kAfterLatch) return "";
      return "is released after panel '" +
             base.model.hinged.panels[static_cast<std::size_t>(d.release.panel)].name +
             "' latches (vary that with release_delay)";
    case Parameter::kReleaseDelay:
      return d.release.kind == Release::Kind::kAfterLatch
                 ? ""
                 : "is not released after another panel's latch (vary its release with "
                   "release_time)";
    default:  // friction_torque: any free hinge (without a regularization speed in the base
              // profile, exact Coulomb friction, schedule::Friction)
      return "";
  }
}

bool IsMoveStage(const schedule::Profile& p, std::size_t i) {
  return i > 0 && p.stages[i].to != p.stages[i - 1].to;
}

int ReadStage(const Fields& f, const schedule::Profile& base) {
  const YamlNode& node = f.Get("stage");
  // A plain (unquoted) run of digits is an index; anything else is a stage name.
  if (node.IsPlainScalar() && !node.Scalar().empty() &&
      node.Scalar().find_first_not_of("0123456789") == std::string::npos) {
    const double x = io::yaml::ReadNumber(f.doc(), node, f.Key("stage"));
    if (x >= static_cast<double>(base.stages.size())) {
      f.Fail("stage", "a stage index must be in [0, " + std::to_string(base.stages.size()) +
                          ") (the stages of " + base.source + ", counted from 0)");
    }
    return static_cast<int>(x);
  }
  const std::string name = f.Text("stage");
  int found = -1;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < base.stages.size(); ++i) {
    names.push_back(base.stages[i].name);
    if (base.stages[i].name == name) {
      if (found >= 0) {
        f.Fail("stage", "the stage name is not unique in " + base.source + ": use its index");
      }
      found = static_cast<int>(i);
    }
  }
  if (found < 0) {
    f.Fail("stage",
           "no stage of that name in " + base.source + " (stages: " + JoinNames(names) + ")");
  }
  return found;
}

/// Per panel of the model: 1 for a hinge an appendage generated (model.h Appendage::hinges).
std::vector<char> GeneratedHinges(const model::Model& m) {
  std::vector<char> g(m.hinged.panels.size(), 0);
  for (const model::Appendage& a : m.appendages) {
    for (int h : a.hinges) g.at(static_cast<std::size_t>(h)) = 1;
  }
  return g;
}

/// The name of the appendage that generated hinge `panel`.
std::string AppendageOf(const model::Model& m, int panel) {
  for (const model::Appendage& a : m.appendages) {
    for (int h : a.hinges) {
      if (h == panel) return a.name;
    }
  }
  return "";
}

/// What an appendage parameter acts on, for messages.
std::string AppendageKinds(Parameter par) {
  switch (par) {
    case Parameter::kDampingRatio:
      return "beams and slosh pendulums given by a damping ratio";
    case Parameter::kFillFraction:
      return "slosh pendulums given by a tank";
    default:
      return "beams";
  }
}

/// The appendage(s) of an appendage parameter: `appendage` (one the parameter acts on,
/// AppliesTo) or, without it, every appendage of the kinds it acts on, each of which must
/// be one it acts on (a slosh pendulum given by its damper has no damping ratio to vary).
void ReadAppendageTarget(const Fields& f,
                         const schedule::Profile& base,
                         const std::string& name,
                         Target& t) {
  const std::vector<model::Appendage>& apps = base.model.appendages;
  const std::string model_name = "model '" + Short(base.model.name) + "'";
  std::vector<std::string> names, acted;
  for (const model::Appendage& a : apps) {
    names.push_back(a.name);
    if (AppliesTo(t.parameter, a)) acted.push_back(a.name);
  }
  if (f.Has("appendage")) {
    const std::string appendage = f.Text("appendage");
    for (std::size_t i = 0; i < apps.size(); ++i) {
      if (apps[i].name == appendage) t.appendage = static_cast<int>(i);
    }
    if (t.appendage < 0) {
      f.Fail("appendage", "no appendage of that name in " + model_name + " (appendages: " +
                              (names.empty() ? std::string("none") : JoinNames(names)) + ")");
    }
    if (appendage.find(',') != std::string::npos) {
      f.Fail("appendage", "appendage names in sweeps must not contain ','");
    }
    if (!AppliesTo(t.parameter, apps[static_cast<std::size_t>(t.appendage)])) {
      f.Fail("appendage", name + " applies to " + AppendageKinds(t.parameter) + " (of " +
                              model_name + ": " +
                              (acted.empty() ? std::string("none") : JoinNames(acted)) + ")");
    }
    t.column += "[" + appendage + "]";
    t.description += " (appendage " + appendage + ")";
    return;
  }
  const bool slosh_kind =
      t.parameter == Parameter::kDampingRatio || t.parameter == Parameter::kFillFraction;
  const bool beam_kind = t.parameter != Parameter::kFillFraction;
  for (const model::Appendage& a : apps) {
    const bool of_kind = (a.beam && beam_kind) || (a.slosh && slosh_kind);
    if (of_kind && !AppliesTo(t.parameter, a)) {
      f.Fail("parameter",
             name +
                 " applies to every appendage of its kinds without `appendage:`, "
                 "but slosh pendulum '" +
                 a.name + "' of " + model_name + " is not given by " +
                 (t.parameter == Parameter::kFillFraction ? "a tank" : "a damping ratio") +
                 " (name the appendages it applies to with `appendage:`)");
    }
  }
  if (acted.empty()) {
    f.Fail("parameter", name + " applies to the model's " + AppendageKinds(t.parameter) + "; " +
                            model_name + " has none");
  }
  t.description += " (every one of: " + JoinNames(acted) + ")";
}

/// The panel(s) of a free-hinge parameter: `panel` (a free panel) or every free panel;
/// each must have what the parameter acts on (NotApplicable).
void ReadHingeTarget(const Fields& f,
                     const schedule::Profile& base,
                     const std::string& name,
                     Entry& e) {
  using schedule::HingePlan;
  Target& t = e.target;
  const std::vector<model::Panel>& panels = base.model.hinged.panels;
  const std::string base_name = base.source.empty() ? base.name : base.source;
  // The appendages' generated hinges take their springs and dampers from the model (vary
  // those with the appendage parameters): not free panels here.
  const std::vector<char> generated = GeneratedHinges(base.model);
  auto is_free = [&](std::size_t i) {
    return base.hinges[i].kind == HingePlan::Kind::kFree && !generated[i];
  };
  std::vector<std::string> free;
  for (std::size_t i = 0; i < panels.size(); ++i) {
    if (is_free(i)) free.push_back(panels[i].name);
  }
  if (f.Has("panel")) {
    const std::string panel = f.Text("panel");
    std::vector<std::string> names;
    for (std::size_t i = 0; i < panels.size(); ++i) {
      names.push_back(panels[i].name);
      if (names.back() == panel) t.panel = static_cast<int>(i);
    }
    if (t.panel < 0) f.Fail("panel", "no panel of that name (panels: " + JoinNames(names) + ")");
    if (panel.find(',') != std::string::npos) {
      f.Fail("panel", "panel names in sweeps must not contain ','");
    }
    const HingePlan& h = base.hinges[static_cast<std::size_t>(t.panel)];
    if (generated[static_cast<std::size_t>(t.panel)]) {
      f.Fail("panel", "a hinge generated by appendage " + AppendageOf(base.model, t.panel) + ": " +
                          name +
                          " applies to the free hinges of the profile; vary the appendage with "
                          "bending_stiffness, bending_stiffness_scale, damping_ratio or "
                          "fill_fraction and `appendage:`");
    }
    if (h.kind != HingePlan::Kind::kFree) {
      f.Fail("panel", "the panel is " + schedule::ToString(h.kind) + " in " + base_name + ": " +
                          name + " applies to free hinges (free panels: " +
                          (free.empty() ? std::string("none") : JoinNames(free)) + ")");
    }
    const std::string why = NotApplicable(t.parameter, h.drive, base);
    if (!why.empty()) f.Fail("panel", name + ": the panel " + why + " in " + base_name);
    t.column += "[" + panel + "]";
    t.description += " (panel " + panel + ")";
  } else {
    if (free.empty()) {
      f.Fail("parameter", name + " applies to free hinges; the base " + base_name +
                              " has none (every panel is locked or prescribed)");
    }
    for (std::size_t i = 0; i < panels.size(); ++i) {
      if (!is_free(i)) continue;
      const std::string why = NotApplicable(t.parameter, base.hinges[i].drive, base);
      if (!why.empty()) {
        f.Fail("parameter", name +
                                " applies to every free panel without `panel:`, but free panel '" +
                                panels[i].name + "' " + why + " in " + base_name +
                                " (name the panels it applies to with `panel:`)");
      }
    }
    t.description += " (every free panel: " + JoinNames(free) + ")";
  }
  if (t.parameter == Parameter::kReleaseTime) {
    e.lower = base.start;
    e.lower_open = false;
    e.rule = "must be >= the base profile's start (" + FormatNumber(base.start) + " s)";
  }
}

Entry ReadTarget(const Fields& f, const schedule::Profile& base) {
  Entry e;
  const std::string name = f.Text("parameter");
  for (const ParameterInfo& p : kParameters) {
    if (name == p.name) e.info = &p;
  }
  if (e.info == nullptr) f.Fail("parameter", "unknown parameter (valid: " + ParameterNames() + ")");
  e.lower = e.info->lower;
  e.lower_open = e.info->lower_open;
  e.upper = e.info->upper;
  e.upper_closed = e.info->upper_closed;
  e.rule = e.info->unit != nullptr ? RangeRule(*e.info) : std::string();
  const Parameter par = e.info->parameter;
  const std::string base_name = base.source.empty() ? base.name : base.source;
  if (IsStageParameter(par) && base.is_hinge_profile()) {
    f.Fail("parameter", name + " applies to stage profiles (`stages:`); the base " + base_name +
                            " is a hinge profile (`hinges:`)");
  }
  if (IsHingeParameter(par) && !base.is_hinge_profile()) {
    f.Fail("parameter", name +
                            " applies to the free hinges of hinge profiles (`hinges:`); the base " +
                            base_name + " is a stage profile (`stages:`)");
  }
  Target& t = e.target;
  t.parameter = par;
  t.column = e.info->column;
  t.description = e.info->description;
  auto only_for = [&f, &name](const char* key, bool allowed) {
    if (f.Has(key) && !allowed) f.Fail(key, "not used by parameter " + name);
  };
  only_for("stage", par == Parameter::kStageDuration || par == Parameter::kLaw);
  only_for("panel", par == Parameter::kPanelMassScale || IsHingeParameter(par));
  only_for("appendage", IsAppendageParameter(par));
  only_for("configuration", par == Parameter::kInertiaScale);
  only_for("axis", par == Parameter::kInertiaScale);
  if (par == Parameter::kStageDuration && !f.Has("stage")) {
    f.doc().Fail(f.Key("stage"), "required key is missing (which stage: index or name)");
  }
  if (f.Has("stage")) {
    t.stage = ReadStage(f, base);
    if (par == Parameter::kLaw && !IsMoveStage(base, static_cast<std::size_t>(t.stage))) {
      f.Fail("stage", "stage " + std::to_string(t.stage) + " of " + base.source +
                          " is a hold: a law applies to move (`to`) stages");
    }
    t.column += "[" + std::to_string(t.stage) + "]";
    t.description += " (stage " + std::to_string(t.stage) + ", '" +
                     Short(base.stages[static_cast<std::size_t>(t.stage)].name) + "')";
  }
  if (par == Parameter::kPanelMassScale) {
    if (base.model.kind != model::ModelKind::kHinged) {
      f.Fail("parameter", "panel_mass_scale needs a hinged model (model '" +
                              Short(base.model.name) + "' is kind tensors; use inertia_scale)");
    }
    if (f.Has("panel")) {
      const std::string panel = f.Text("panel");
      std::vector<std::string> names;
      for (std::size_t i = 0; i < base.model.hinged.panels.size(); ++i) {
        names.push_back(base.model.hinged.panels[i].name);
        if (names.back() == panel) t.panel = static_cast<int>(i);
      }
      if (t.panel < 0) f.Fail("panel", "no panel of that name (panels: " + JoinNames(names) + ")");
      if (panel.find(',') != std::string::npos)
        f.Fail("panel", "panel names in sweeps must not contain ','");
      t.column += "[" + panel + "]";
      t.description += " (panel " + panel + ")";
    }
  }
  if (IsHingeParameter(par)) ReadHingeTarget(f, base, name, e);
  if (IsAppendageParameter(par)) ReadAppendageTarget(f, base, name, t);
  if (par == Parameter::kInertiaScale) {
    if (base.model.kind != model::ModelKind::kTensors) {
      f.Fail("parameter", "inertia_scale needs a tensors model (model '" + Short(base.model.name) +
                              "' is hinged; use panel_mass_scale)");
    }
    std::string qualifier;
    if (f.Has("configuration")) {
      t.configuration = f.Text("configuration");
      std::vector<std::string> names;
      for (const model::Configuration& c : base.model.configurations) names.push_back(c.name);
      if (std::find(names.begin(), names.end(), t.configuration) == names.end()) {
        f.Fail("configuration", "no configuration of that name in model '" +
                                    Short(base.model.name) + "' (valid: " + JoinNames(names) + ")");
      }
      if (t.configuration.find(',') != std::string::npos) {
        f.Fail("configuration", "configuration names in sweeps must not contain ','");
      }
      qualifier = t.configuration;
    }
    if (f.Has("axis")) {
      const std::string axis = f.Text("axis");
      if (axis != "x" && axis != "y" && axis != "z") f.Fail("axis", "must be x, y or z");
      t.axis = axis[0] - 'x';
      qualifier += (qualifier.empty() ? "" : ".") + axis;
      t.description += "; J_B -> S J_B S with S = I except S_" + axis + axis + " = sqrt(factor)";
    }
    if (!qualifier.empty()) t.column += "[" + qualifier + "]";
  }
  return e;
}

/// A number of the parameter's kind at `key` (file units), checked against its range.
double ReadValue(const Fields& f, const YamlNode& node, const std::string& key, const Entry& e) {
  const double v = io::yaml::ReadNumber(f.doc(), node, key);
  if (!e.InRange(v)) f.doc().Fail(key, node, std::string(e.info->name) + " " + e.rule);
  return v * e.info->to_si;
}

/// A category name of a categorical parameter -> its code.
double ReadCategory(const Fields& f,
                    const YamlNode& node,
                    const std::string& key,
                    const ParameterInfo& p) {
  const std::string name = io::yaml::ReadText(f.doc(), node, key);
  const std::vector<std::string>& cats = CategoriesOf(p.parameter);
  for (std::size_t i = 0; i < cats.size(); ++i) {
    if (cats[i] == name) return static_cast<double>(i);
  }
  f.doc().Fail(key, node, std::string("unknown ") + p.name + " (valid: " + JoinNames(cats) + ")");
}

double ReadCount(const Fields& f, const YamlNode& node, const std::string& key, double min) {
  const double n = io::yaml::ReadNumber(f.doc(), node, key);
  if (n != std::floor(n) || n < min || n > kMaxAxisValues) {
    f.doc().Fail(
        key, node,
        "must be an integer in [" + FormatNumber(min) + ", " + FormatNumber(kMaxAxisValues) + "]");
  }
  return n;
}

/// The values of one grid axis. `cases` is the number of cases of the axes before it: an
/// axis that would take the sweep past kMaxCases is refused before its values are made (a
/// few lines of linspace axes would otherwise allocate gigabytes).
std::vector<double> ReadGridValues(const Fields& f, const Entry& e, double cases) {
  const ParameterInfo& p = *e.info;
  auto check_cases = [&f, cases](const std::string& key, double count) {
    if (cases * count > kMaxCases) {
      f.Fail(key, "gives " + FormatNumber(cases * count) +
                      " cases with the axes before it (at most " + FormatNumber(kMaxCases) + ")");
    }
  };
  const bool categorical = IsCategorical(p.parameter);
  const char* keys[] = {"values", "linspace", "logspace"};
  int given = 0;
  for (const char* k : keys) given += f.Has(k) ? 1 : 0;
  if (given != 1) {
    f.doc().Fail(f.path(), f.node(),
                 std::string("exactly one of values, linspace, logspace is required (") +
                     (given == 0 ? "none" : "several") + " given)");
  }
  std::vector<double> values;
  if (f.Has("values")) {
    const std::vector<YamlNode> nodes =
        io::yaml::SequenceElements(f.doc(), f.Get("values"), f.Key("values"), "values");
    if (nodes.empty()) f.Fail("values", "at least one value is required");
    check_cases("values", static_cast<double>(nodes.size()));
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const std::string key = f.Key("values") + "[" + std::to_string(i) + "]";
      values.push_back(categorical ? ReadCategory(f, nodes[i], key, p)
                                   : ReadValue(f, nodes[i], key, e));
    }
    if (static_cast<double>(values.size()) > kMaxAxisValues) {
      f.Fail("values", "at most " + FormatNumber(kMaxAxisValues) + " values per axis");
    }
    return values;
  }
  const bool log = f.Has("logspace");
  const std::string key = log ? "logspace" : "linspace";
  if (categorical) f.Fail(key, std::string(p.name) + " takes `values` (names), not " + key);
  const std::vector<YamlNode> nodes =
      io::yaml::SequenceElements(f.doc(), f.Get(key), f.Key(key), key);
  if (nodes.size() != 3) f.Fail(key, "must be [first, last, count]");
  const double a = ReadValue(f, nodes[0], f.Key(key) + "[0]", e);
  const double b = ReadValue(f, nodes[1], f.Key(key) + "[1]", e);
  const double n = ReadCount(f, nodes[2], f.Key(key) + "[2]", 2.0);
  if (log && !(a > 0.0 && b > 0.0)) f.Fail(key, "logspace needs first and last > 0");
  if (a == b) f.Fail(key, "first and last must differ");
  check_cases(key, n);
  const std::size_t count = static_cast<std::size_t>(n);
  for (std::size_t i = 0; i < count; ++i) {
    const double u = static_cast<double>(i) / static_cast<double>(count - 1);
    double v = log ? a * std::pow(b / a, u) : a + (b - a) * u;
    if (i == count - 1) v = b;  // the end point exactly as written
    values.push_back(v);
  }
  return values;
}

Distribution ReadDistribution(const Fields& f, const Entry& e) {
  const ParameterInfo& p = *e.info;
  const bool categorical = IsCategorical(p.parameter);
  const char* keys[] = {"uniform", "normal", "choice"};
  int given = 0;
  for (const char* k : keys) given += f.Has(k) ? 1 : 0;
  if (given != 1) {
    f.doc().Fail(f.path(), f.node(),
                 std::string("exactly one of uniform, normal, choice is required (") +
                     (given == 0 ? "none" : "several") + " given)");
  }
  Distribution d;
  if (f.Has("weights") && !f.Has("choice")) f.Fail("weights", "weights go with choice");
  if (f.Has("choice")) {
    d.kind = Distribution::Kind::kChoice;
    const std::vector<YamlNode> nodes =
        io::yaml::SequenceElements(f.doc(), f.Get("choice"), f.Key("choice"), "choice");
    if (nodes.empty()) f.Fail("choice", "at least one choice is required");
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const std::string key = f.Key("choice") + "[" + std::to_string(i) + "]";
      d.choices.push_back(categorical ? ReadCategory(f, nodes[i], key, p)
                                      : ReadValue(f, nodes[i], key, e));
    }
    if (f.Has("weights")) {
      const std::vector<YamlNode> w =
          io::yaml::SequenceElements(f.doc(), f.Get("weights"), f.Key("weights"), "weights");
      if (w.size() != nodes.size()) {
        f.Fail("weights",
               "one weight per choice is required (" + std::to_string(nodes.size()) + " choices)");
      }
      double total = 0.0;
      for (std::size_t i = 0; i < w.size(); ++i) {
        const std::string key = f.Key("weights") + "[" + std::to_string(i) + "]";
        const double x = io::yaml::ReadNumber(f.doc(), w[i], key);
        if (!(x >= 0.0)) f.doc().Fail(key, w[i], "a weight must be >= 0");
        total += x;
        d.cumulative.push_back(total);
      }
      if (!(total > 0.0)) f.Fail("weights", "at least one weight must be > 0");
      for (double& c : d.cumulative) c /= total;
      d.cumulative.back() = 1.0;
    }
    return d;
  }
  if (categorical) {
    f.Fail(f.Has("uniform") ? "uniform" : "normal",
           std::string(p.name) + " is categorical: use choice: [names]");
  }
  if (f.Has("uniform")) {
    d.kind = Distribution::Kind::kUniform;
    const std::vector<YamlNode> nodes =
        io::yaml::SequenceElements(f.doc(), f.Get("uniform"), f.Key("uniform"), "uniform");
    if (nodes.size() != 2) f.Fail("uniform", "must be [low, high]");
    d.a = ReadValue(f, nodes[0], f.Key("uniform") + "[0]", e);
    d.b = ReadValue(f, nodes[1], f.Key("uniform") + "[1]", e);
    if (!(d.a < d.b)) f.Fail("uniform", "low must be < high");
    return d;
  }
  d.kind = Distribution::Kind::kNormal;
  const Fields n = f.Mapping("normal", {"mean", "sigma", "min", "max"});
  const double mean = n.Number("mean");
  const double sigma = n.Number("sigma");
  if (!(sigma > 0.0)) n.Fail("sigma", "must be > 0");
  d.a = mean * p.to_si;
  d.b = sigma * p.to_si;
  const bool bounded_below = e.lower > -kInf;
  const bool bounded_above = e.upper < kInf;
  if (n.Has("min")) {
    d.min = ReadValue(f, n.Get("min"), n.Key("min"), e);
  } else if (bounded_below) {
    n.doc().Fail(n.Key("min"), std::string("required key is missing: a normal distribution of ") +
                                   p.name + " needs a truncation bound min (" + p.name + " " +
                                   e.rule + ")");
  }
  if (n.Has("max")) {
    d.max = ReadValue(f, n.Get("max"), n.Key("max"), e);
  } else if (bounded_above) {
    n.doc().Fail(n.Key("max"), std::string("required key is missing: a normal distribution of ") +
                                   p.name + " needs a truncation bound max (" + p.name + " " +
                                   e.rule + ")");
  }
  if (n.Has("min") && n.Has("max") && !(d.min < d.max)) n.Fail("max", "must be > min");
  // The bounds must keep a reasonable share of the distribution (rejection sampling).
  const double lo = (d.min - d.a) / d.b;
  const double hi = (d.max - d.a) / d.b;
  if (lo > 3.0 || hi < -3.0) {
    n.Fail("mean", "the truncation bounds [min, max] lie more than 3 sigma from the mean");
  }
  return d;
}

void ReadIntegrator(const Fields& top, schedule::Profile& base) {
  if (!top.Has("integrator")) return;
  const Fields f = top.Mapping("integrator", {"method", "rtol", "atol", "step", "max_step"});
  schedule::IntegratorSpec& s = base.integrator;
  if (f.Has("method")) {
    s.method = f.Text("method");
    const std::string rule = analysis::MethodRuleViolated(s.method);
    if (!rule.empty()) f.Fail("method", rule);
  }
  for (const auto& [key, value] : {std::pair<const char*, double*>{"rtol", &s.rtol},
                                   {"atol", &s.atol},
                                   {"step", &s.step},
                                   {"max_step", &s.max_step}}) {
    if (!f.Has(key)) continue;
    *value = f.Number(key);
    const std::string rule = schedule::IntegratorRuleViolated(key, *value);
    if (!rule.empty()) f.Fail(key, rule);
  }
  const std::string step_rule = analysis::StepRuleViolated(s.method, s.step);
  if (!step_rule.empty()) {
    top.doc().Fail(f.Key(f.Has("method") ? "method" : "step"),
                   f.Get(f.Has("method") ? "method" : "step"), step_rule);
  }
}

/// Free hinges are integrated by a Lie-group method (run::HingeBody): a hinge
/// base with a free hinge and another method would fail in every case.
void RequireShapeMethod(const Fields& top, const schedule::Profile& base) {
  const std::string& method = base.integrator.method;
  if (!base.has_free_hinge() || analysis::RunsFreeHinges(method)) return;
  const std::string rule = ": " + analysis::FreeHingeMethodRule();
  if (top.Has("integrator")) {
    const Fields f = top.Mapping("integrator", {"method", "rtol", "atol", "step", "max_step"});
    if (f.Has("method")) f.Fail("method", "the base " + base.source + " has free hinges" + rule);
  }
  top.Fail("base", "integrator.method = " + method + " in the base profile" + rule);
}

}  // namespace

void ValidateCases(const SweepSpec& spec) {
  // The cases are built from a copy without the texts and descriptions, which no check
  // reads: each may have up to 1 MiB (io::yaml::kMaxFileBytes), and every case copies its
  // base profile.
  SweepSpec light = spec;
  light.text.clear();
  light.description.clear();
  light.model_text.clear();
  light.base.text.clear();
  light.base.description.clear();
  light.base.model.text.clear();
  light.base.model.description.clear();
  // Every case once, on all hardware threads (building a case costs ~5% of running it);
  // the error reported is that of the lowest failing case, as a serial loop would
  // (ParallelFor's rule).
  ParallelOptions parallel;
  parallel.chunk = 64;
  ParallelFor(
      light.case_count(), [&light](std::size_t i) { (void)BuildCase(light, i); }, parallel);
}

SweepSpec LoadSweep(const std::string& path) {
  SweepSpec spec = ReadSweep(path);
  ValidateCases(spec);
  return spec;
}

SweepSpec ReadSweep(const std::string& path) {
  const std::string text = io::yaml::ReadTextFile(path);
  return ReadSweepText(text, path, std::filesystem::path(path).parent_path().string());
}

SweepSpec LoadSweepText(const std::string& text,
                        const std::string& source,
                        const std::string& base_dir,
                        const schedule::Profile* base) {
  SweepSpec spec = ReadSweepText(text, source, base_dir, base);
  ValidateCases(spec);
  return spec;
}

SweepSpec ReadSweepText(const std::string& text,
                        const std::string& source,
                        const std::string& base_dir,
                        const schedule::Profile* base) {
  const std::string& path = source;
  const YamlDocument doc(source, text, base_dir);
  const Fields top(doc, doc.root(), "",
                   {"name", "description", "base", "integrator", "grid", "monte_carlo", "outcome"});
  SweepSpec spec;
  spec.source = path;
  spec.text = doc.text();
  spec.name = top.Name("name");
  spec.description = top.OptionalText("description").value_or("");
  if (base != nullptr) {
    (void)top.Text("base");  // still required, and a string: the profile's name or file
    spec.base = *base;
    spec.model_text = base->model.text;
  } else {
    spec.base = io::LoadProfile(top.FilePath("base"));
    spec.model_text = io::yaml::ReadTextFile(spec.base.model.source);
  }
  ReadIntegrator(top, spec.base);
  RequireShapeMethod(top, spec.base);
  if (!top.Has("grid") && !top.Has("monte_carlo")) {
    doc.Fail("grid", "required key is missing: a sweep needs a grid, monte_carlo, or both");
  }

  std::vector<std::pair<std::string, std::string>> columns;  // column, key path
  auto claim = [&doc, &columns](const Fields& f, const Target& t) {
    for (const auto& [column, key] : columns) {
      if (column == t.column) {
        doc.Fail(f.Key("parameter"), f.Get("parameter"),
                 "sets column " + t.column + " again (already set by " + key + ")");
      }
    }
    columns.emplace_back(t.column, f.path());
  };
  const std::vector<std::string> target_keys = {"parameter",     "stage", "panel",
                                                "configuration", "axis",  "appendage"};
  auto with = [&target_keys](std::vector<std::string> extra) {
    extra.insert(extra.end(), target_keys.begin(), target_keys.end());
    return extra;
  };

  double cases = 1.0;
  if (top.Has("grid")) {
    const std::vector<YamlNode> axes =
        io::yaml::SequenceElements(doc, top.Get("grid"), "grid", "grid");
    if (axes.empty()) top.Fail("grid", "at least one axis is required (or leave grid out)");
    for (std::size_t k = 0; k < axes.size(); ++k) {
      const Fields f(doc, axes[k], "grid[" + std::to_string(k) + "]",
                     with({"values", "linspace", "logspace"}));
      const Entry e = ReadTarget(f, spec.base);
      claim(f, e.target);
      GridAxis axis{e.target, ReadGridValues(f, e, cases)};
      cases *= static_cast<double>(axis.values.size());
      spec.grid.push_back(std::move(axis));
    }
  }
  if (top.Has("monte_carlo")) {
    const Fields m = top.Mapping("monte_carlo", {"samples", "seed", "parameters"});
    MonteCarlo mc;
    mc.samples = static_cast<std::size_t>(ReadCount(m, m.Get("samples"), m.Key("samples"), 1.0));
    const double seed = m.Number("seed");
    if (seed != std::floor(seed) || seed < 0.0 || seed > kMaxSeed) {
      m.Fail("seed", "must be an integer in [0, 2^53]");
    }
    mc.seed = static_cast<std::uint64_t>(seed);
    const std::vector<YamlNode> params =
        io::yaml::SequenceElements(doc, m.Get("parameters"), m.Key("parameters"), "parameters");
    if (params.empty()) m.Fail("parameters", "at least one parameter is required");
    for (std::size_t k = 0; k < params.size(); ++k) {
      const Fields f(doc, params[k], m.Key("parameters") + "[" + std::to_string(k) + "]",
                     with({"uniform", "normal", "choice", "weights"}));
      const Entry e = ReadTarget(f, spec.base);
      claim(f, e.target);
      mc.parameters.push_back({e.target, ReadDistribution(f, e)});
    }
    cases *= static_cast<double>(mc.samples);
    spec.monte_carlo = std::move(mc);
  }
  if (cases > kMaxCases) {
    doc.Fail(top.Has("grid") ? "grid" : "monte_carlo",
             top.Get(top.Has("grid") ? "grid" : "monte_carlo"),
             "gives " + FormatNumber(cases) + " cases (at most " + FormatNumber(kMaxCases) + ")");
  }
  if (top.Has("outcome")) {
    const Fields o = top.Mapping("outcome", {"tumble_angle_deg", "latch_shock_limit_deg_s"});
    if (o.Has("tumble_angle_deg")) {
      const double a = o.Number("tumble_angle_deg");
      if (!(a > 0.0 && a < 90.0)) o.Fail("tumble_angle_deg", "must be in (0, 90) [deg]");
      spec.outcome.tumble_angle = a * kDegree;
    }
    if (o.Has("latch_shock_limit_deg_s")) {
      const double a = o.Number("latch_shock_limit_deg_s");
      if (!(a > 0.0)) o.Fail("latch_shock_limit_deg_s", "must be > 0 [deg/s]");
      if (!spec.base.is_hinge_profile()) {
        o.Fail("latch_shock_limit_deg_s",
               "a latch shock limit needs a hinge profile as the base (stage profiles have no "
               "latches)");
      }
      spec.outcome.latch_shock_limit = a * kDegree;
    }
  }
  spec.base_spin_axis_B = BaseSpinAxis(spec.base);
  return spec;
}

}  // namespace deploysim::sweep
