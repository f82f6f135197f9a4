#include "deploysim/schedule/profile.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "deploysim/math/inertia.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/units.h"
#include "deploysim/model/mass_properties.h"

namespace deploysim::schedule {

namespace {

/// The project's number formatting (math/number_format.h) under a short local name.
constexpr auto& Num = math::FormatNumber;
using math::kDegreesPerRadian;

std::string Vec(const Eigen::VectorXd& v) {
  std::string s = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) s += (i ? ", " : "") + Num(v[i]);
  return s + "]";
}

/// Rejects the profile: "<where>: <message>".
[[noreturn]] void Fail(const std::string& where, const std::string& message) {
  throw std::invalid_argument(where + ": " + message);
}

const model::Configuration* FindConfiguration(const model::Model& m, const std::string& name) {
  for (const model::Configuration& c : m.configurations) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::string ConfigurationNames(const model::Model& m) {
  std::string names;
  for (const model::Configuration& c : m.configurations) {
    names += (names.empty() ? "" : ", ") + c.name;
  }
  return names;
}

void RequireConfiguration(const Profile& p,
                          const std::string& where,
                          const std::string& key,
                          const std::string& name) {
  if (FindConfiguration(p.model, name) != nullptr) return;
  Fail(where, key + " = '" + name + "': no configuration of that name in model '" + p.model.name +
                  "' (valid: " + ConfigurationNames(p.model) + ")");
}

void ValidateModel(const Profile& p, const std::string& where) {
  const model::Model& m = p.model;
  const std::string model_where = m.source.empty() ? where + ": model" : m.source;
  if (m.kind == model::ModelKind::kHinged) {
    // Throws with its own message (masses, inertias, hinge axes).
    (void)model::ValidatedHingedBody(m.hinged, model_where);
    const std::size_t panels = m.hinged.panels.size();
    for (const model::Configuration& c : m.configurations) {
      const std::string key = "configurations." + c.name + ".hinge_angles_deg";
      if (static_cast<std::size_t>(c.hinge_angles.size()) != panels) {
        Fail(model_where, key + " has " + std::to_string(c.hinge_angles.size()) +
                              " entries: one hinge angle per panel is required (the model has " +
                              std::to_string(panels) + " panels)");
      }
      if (!c.hinge_angles.allFinite()) {
        Fail(model_where, key + " = " + Vec(c.hinge_angles) + " [rad]: must be finite");
      }
      // The angles a hinge may be driven to (kMaxDriveAngle): a spring stretched over more
      // turns than that drives no physical panel, and its torque overflows the steps.
      for (Eigen::Index k = 0; k < c.hinge_angles.size(); ++k) {
        if (!(std::abs(c.hinge_angles[k]) <= kMaxDriveAngle)) {
          Fail(model_where,
               key + "[" + std::to_string(k) + "] = " + Num(c.hinge_angles[k] * kDegreesPerRadian) +
                   " deg: must be within +-" + Num(kMaxDriveAngle * kDegreesPerRadian) + " deg");
        }
      }
    }
  } else {
    for (const model::Configuration& c : m.configurations) {
      const std::string err =
          math::InertiaTensor::Check(c.J_B, model_where + ": configurations." + c.name);
      if (!err.empty()) throw std::invalid_argument(err);
    }
  }
}

void ValidateModes(const Profile& p, const std::string& where) {
  if (p.mode == Mode::kGeometry && p.model.kind != model::ModelKind::kHinged) {
    Fail(where, "mode = geometry: geometry mode needs a hinged model (model '" + p.model.name +
                    "' is kind tensors)");
  }
  if (p.coupling == Coupling::kExact && p.mode != Mode::kGeometry) {
    Fail(where,
         "coupling = exact: exact coupling needs mode geometry (mode is " + ToString(p.mode) + ")");
  }
}

void ValidateStages(const Profile& p, const std::string& where) {
  if (p.stages.empty()) Fail(where, "stages: at least one stage is required");
  for (std::size_t i = 0; i < p.stages.size(); ++i) {
    const Stage& st = p.stages[i];
    const std::string key = "stages[" + std::to_string(i) + "]";
    // Times.
    if (i == 0 && !std::isfinite(st.t_begin)) {
      Fail(where, key + ".start = " + Num(st.t_begin) + ": must be finite");
    }
    if (!std::isfinite(st.t_end)) {
      Fail(where, key + ".until = " + Num(st.t_end) + ": must be finite");
    }
    if (i > 0) {
      const double prev_end = p.stages[i - 1].t_end;
      if (st.t_begin != prev_end) {
        Fail(where, key + ".start = " + Num(st.t_begin) +
                        ": stages must be contiguous (previous stage ends at " + Num(prev_end) +
                        ")");
      }
      if (!(st.t_end > st.t_begin)) {
        Fail(where, key + ".until = " + Num(st.t_end) +
                        ": stage end times must increase (previous stage ends at " + Num(prev_end) +
                        ")");
      }
    } else if (!(st.t_end > st.t_begin)) {
      Fail(where, key + ".until = " + Num(st.t_end) +
                      ": stage end times must increase (the first stage starts at " +
                      Num(st.t_begin) + ")");
    }
    // Configurations. A hold names its configuration with `hold`, a move with `to`.
    RequireConfiguration(p, where, key + (st.is_hold() ? ".hold" : ".to"), st.to);
    if (i == 0) {
      if (st.from.empty()) {
        Fail(where, key + ".to = '" + st.to +
                        "': the first stage must be a hold or name the configuration it "
                        "starts from (there is no previous stage)");
      }
      RequireConfiguration(p, where, key + ".from", st.from);
    } else if (!st.from.empty()) {
      RequireConfiguration(p, where, key + ".from", st.from);
      const std::string& prev_to = p.stages[i - 1].to;
      if (st.from != prev_to) {
        Fail(where, key + ".from = '" + st.from +
                        "': a stage starts in the configuration the previous stage ends in ('" +
                        prev_to + "'); switch configurations with a step-law stage");
      }
    }
    // Laws. A hold ignores its law; a move with `step` switches instantaneously.
    const bool moves = st.from.empty() ? st.to != p.stages[i - 1].to : !st.is_hold();
    if (moves && st.law == Law::kStep && p.coupling == Coupling::kExact) {
      Fail(where, key +
                      ".law = step: the step law is not allowed with coupling exact (an "
                      "instantaneous hinge motion carries an impulsive relative momentum)");
    }
  }
  // Durations, once every time is known to be finite and increasing.
  const double scale =
      std::max(std::abs(p.stages.front().t_begin), std::abs(p.stages.back().t_end));
  const double min_duration = kMinStageDurationFraction * scale;
  for (std::size_t i = 0; i < p.stages.size(); ++i) {
    const Stage& st = p.stages[i];
    const double duration = st.t_end - st.t_begin;
    if (!(duration >= min_duration)) {
      Fail(where, "stages[" + std::to_string(i) + "].until = " + Num(st.t_end) + ": stage '" +
                      st.name + "' lasts " + Num(duration) + " s, less than the minimum " +
                      Num(min_duration) + " s = " + Num(kMinStageDurationFraction) +
                      " x max(|start|, |end|) of the profile (" + Num(scale) +
                      " s) (rule: minimum stage duration)");
    }
  }
}

void ValidateInitial(const Profile& p, const std::string& where) {
  const InitialState& in = p.initial;
  const math::Quat& q = in.q_NB;
  const Eigen::Vector4d q_wxyz(q.w(), q.x(), q.y(), q.z());
  if (!q_wxyz.allFinite() || q_wxyz.norm() == 0.0) {
    Fail(where, "initial.attitude_wxyz = " + Vec(q_wxyz) + ": must be finite and non-zero");
  }
  // A spin (InitialSpin) resolves to H_B after this check; before, neither is set.
  if (in.spin) {
    if (in.w_NB_B) Fail(where, "initial: angular_velocity and spin are both given");
    if (!in.spin->axis_B.allFinite() || !(in.spin->axis_B.norm() > 0.0)) {
      Fail(where, "initial.spin.axis: must be finite and non-zero");
    }
    if (!(in.spin->rate > 0.0) || !std::isfinite(in.spin->rate)) {
      Fail(where, "initial.spin.rate = " + Num(in.spin->rate) + " rad/s: must be finite and > 0");
    }
    if (!in.H_B) return;
  } else if (in.w_NB_B.has_value() == in.H_B.has_value()) {
    Fail(where, std::string("initial: exactly one of angular_velocity, angular_momentum is "
                            "required (") +
                    (in.w_NB_B ? "both are" : "neither is") + " given)");
  }
  const std::string key = in.w_NB_B ? "initial.angular_velocity" : "initial.angular_momentum";
  const math::Vec3& v = in.w_NB_B ? *in.w_NB_B : *in.H_B;
  if (!v.allFinite()) Fail(where, key + " = " + Vec(v) + ": must be finite");
  if (v.isZero(0.0)) {
    Fail(where, key + " = " + Vec(v) + ": must be non-zero (a body at rest has no spin to study)");
  }
}

// --- Hinge profiles (`hinges:`, hinge_plan.h, docs/file_formats.md "Hinge profiles") ------

/// An angle [rad] (or a rate [rad/s]) as the file gives it, in degrees (deg/s), to 12
/// significant digits: the file's `95` reads back as "95", not "95.00000000000001".
std::string Deg(double rad) {
  if (!std::isfinite(rad)) return Num(rad);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", rad * kDegreesPerRadian);
  return buf;
}

/// "[min, max] deg" of a hinge's stops (-inf / inf where there is none).
std::string StopRange(const Stops& s) {
  return "[" + Deg(s.min_angle) + ", " + Deg(s.max_angle) + "] deg";
}

/// A hinge profile: no stages, a hinged model, geometry mode with exact coupling.
void ValidateHingeModes(const Profile& p, const std::string& where) {
  if (!p.stages.empty()) {
    Fail(where,
         "stages: a profile has either stages (every panel through the stages' "
         "configurations) or hinges (a plan per panel), not both");
  }
  if (p.model.kind != model::ModelKind::kHinged) {
    Fail(where, "model: hinges need a hinged model (model '" + p.model.name + "' is kind tensors)");
  }
  if (p.mode != Mode::kGeometry) {
    Fail(where, "mode = " + ToString(p.mode) +
                    ": a hinge profile runs in geometry mode (the hinge angles are the state)");
  }
  if (p.coupling != Coupling::kExact) {
    Fail(where, "coupling = " + ToString(p.coupling) +
                    ": a hinge profile runs with exact coupling (the hinge rates enter the "
                    "momentum)");
  }
}

/// start, until and the initial configuration of a hinge profile.
void ValidateHingeRun(const Profile& p, const std::string& where) {
  if (!std::isfinite(p.start)) Fail(where, "start = " + Num(p.start) + ": must be finite");
  if (!std::isfinite(p.until)) Fail(where, "until = " + Num(p.until) + ": must be finite");
  if (!(p.until > p.start)) {
    Fail(where, "until = " + Num(p.until) + ": must be > start (" + Num(p.start) + " s)");
  }
  const double scale = std::max(std::abs(p.start), std::abs(p.until));
  const double min_duration = kMinStageDurationFraction * scale;
  if (!(p.until - p.start >= min_duration)) {
    Fail(where, "until = " + Num(p.until) + ": the run lasts " + Num(p.until - p.start) +
                    " s, less than the minimum " + Num(min_duration) +
                    " s = " + Num(kMinStageDurationFraction) +
                    " x max(|start|, |until|) (rule: minimum run duration)");
  }
  if (p.initial.configuration.empty()) {
    Fail(where,
         "initial.configuration: required key is missing (a hinge profile names the model "
         "configuration that gives the hinge angles at start)");
  }
  RequireConfiguration(p, where, "initial.configuration", p.initial.configuration);
}

/// The moves of a prescribed hinge: ascending windows that do not overlap, each after the
/// profile's start, no step law.
void ValidateMoves(const Profile& p,
                   const std::string& where,
                   const std::string& key,
                   const std::vector<HingeMove>& moves) {
  if (moves.empty()) {
    Fail(where, key +
                    ": at least one move is required (a hinge that does not move: locked: true, "
                    "or leave the panel out)");
  }
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const HingeMove& mv = moves[i];
    const std::string mk = key + "[" + std::to_string(i) + "]";
    if (!std::isfinite(mv.t_begin))
      Fail(where, mk + ".start = " + Num(mv.t_begin) + ": must be finite");
    if (!std::isfinite(mv.t_end))
      Fail(where, mk + ".until = " + Num(mv.t_end) + ": must be finite");
    if (mv.kind == HingeMove::Kind::kTo) {
      if (!std::isfinite(mv.angle))
        Fail(where, mk + ".to_deg = " + Deg(mv.angle) + ": must be finite");
      if (mv.law == Law::kStep) {
        Fail(where, mk + ".law = step: the step law is not allowed for a hinge (an instantaneous "
                         "hinge motion carries an impulsive relative momentum; use linear, "
                         "smoothstep or minimum-jerk)");
      }
    } else if (!std::isfinite(mv.rate)) {
      Fail(where, mk + ".rate_deg_s = " + Deg(mv.rate) + ": must be finite");
    }
    if (!(mv.t_begin >= p.start)) {
      Fail(where, mk + ".start = " + Num(mv.t_begin) +
                      ": a move starts at or after the profile's start (" + Num(p.start) + " s)");
    }
    if (i > 0 && !(mv.t_begin >= moves[i - 1].t_end)) {
      Fail(where, mk + ".start = " + Num(mv.t_begin) +
                      ": the moves of a hinge are in time order and do not overlap (the "
                      "previous move ends at " +
                      Num(moves[i - 1].t_end) + " s)");
    }
    if (!(mv.t_end > mv.t_begin)) {
      Fail(where, mk + ".until = " + Num(mv.t_end) +
                      ": a move ends after it starts (start = " + Num(mv.t_begin) + " s)");
    }
    // Window ends are integrator breakpoints, as stage boundaries are (kMinStageDurationFraction).
    const double scale = std::max({std::abs(p.start), std::abs(p.until), std::abs(mv.t_end)});
    const double min_duration = kMinStageDurationFraction * scale;
    if (!(mv.t_end - mv.t_begin >= min_duration)) {
      Fail(where, mk + ".until = " + Num(mv.t_end) + ": the move lasts " +
                      Num(mv.t_end - mv.t_begin) + " s, less than the minimum " +
                      Num(min_duration) + " s = " + Num(kMinStageDurationFraction) +
                      " x the time scale (" + Num(scale) + " s) (rule: minimum move duration)");
    }
  }
}

/// Checks one value of a free hinge's drive (key: "hinges.<panel>.free").
struct DriveCheck {
  const std::string& where;
  const std::string& key;

  /// `key + sub` is finite and obeys `ok` (else the rule is cited); `degrees`: shown in
  /// degrees (a `_deg` or `_deg_s` key).
  void operator()(const std::string& sub,
                  double value,
                  bool ok,
                  const std::string& rule,
                  bool degrees = false) const {
    const std::string shown = degrees ? Deg(value) : Num(value);
    if (!std::isfinite(value)) Fail(where, key + sub + " = " + shown + ": must be finite");
    if (!ok) Fail(where, key + sub + " = " + shown + ": " + rule);
  }
  /// `key + sub` within +-limit (hinge_plan.h, the accepted ranges); `unit` as shown.
  void Range(const std::string& sub,
             double value,
             double limit,
             const std::string& unit,
             bool degrees = false) const {
    const std::string shown = degrees ? Deg(limit) : Num(limit);
    (*this)(sub, value, std::abs(value) <= limit,
            "must be within +-" + shown + " " + unit + " (rule: accepted range of a free hinge)",
            degrees);
  }
};

/// The drive's motor: its parameters by kind (a servo's moves as a prescribed hinge's).
void ValidateMotor(const Profile& p, const DriveCheck& require, const Motor& mo) {
  const std::string& where = require.where;
  const std::string& key = require.key;
  if (mo.kind == Motor::Kind::kConstant) {
    require.Range(".motor.torque", mo.torque, kMaxDriveTorque, "N m");
  } else if (mo.kind == Motor::Kind::kTorqueSpeed) {
    require.Range(".motor.stall_torque", mo.stall_torque, kMaxDriveTorque, "N m");
    require.Range(".motor.no_load_speed_deg_s", mo.no_load_speed, kMaxDriveSpeed, "deg/s", true);
    require(".motor.stall_torque", mo.stall_torque, mo.stall_torque != 0.0,
            "must be non-zero [N m] (the torque at rest; its sign is the direction the motor "
            "drives)");
    require(".motor.no_load_speed_deg_s", mo.no_load_speed, mo.no_load_speed != 0.0,
            "must be non-zero (the speed at which the motor's torque falls to zero)", true);
    if ((mo.stall_torque > 0.0) != (mo.no_load_speed > 0.0)) {
      Fail(where, key + ".motor.no_load_speed_deg_s = " + Deg(mo.no_load_speed) +
                      ": must have the sign of stall_torque (" + Num(mo.stall_torque) +
                      " N m): the motor drives one way, with torque stall_torque (1 - rate / "
                      "no_load_speed)");
    }
  } else if (mo.kind == Motor::Kind::kServo) {
    require(".motor.servo_stiffness", mo.servo_stiffness, mo.servo_stiffness > 0.0,
            "must be > 0 [N m/rad] (the servo's torque per radian of tracking error)");
    require(".motor.servo_damping", mo.servo_damping, mo.servo_damping >= 0.0,
            "must be >= 0 [N m s/rad]");
    require.Range(".motor.servo_stiffness", mo.servo_stiffness, kMaxDriveStiffness, "N m/rad");
    require.Range(".motor.servo_damping", mo.servo_damping, kMaxDriveDamping, "N m s/rad");
    ValidateMoves(p, where, key + ".motor.follow", mo.follow);
  }
}

/// The hinge's initial angle as messages show it: "<deg> deg in configuration '<name>'".
std::string InitialAngleText(const Profile& p, double theta0) {
  return Deg(theta0) + " deg in configuration '" + p.initial.configuration + "'";
}

/// The drive's stops: ordered limits, a restitution in [0, 1] that has a stop to rebound
/// from, and the initial angle theta0 within them.
void ValidateStops(const Profile& p, const DriveCheck& require, const Stops& st, double theta0) {
  const std::string& where = require.where;
  const std::string& key = require.key;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (std::isnan(st.min_angle) || st.min_angle == kInf) {
    Fail(where, key + ".stops.min_deg = " + Deg(st.min_angle) +
                    ": must be finite (leave it out for no stop)");
  }
  if (std::isnan(st.max_angle) || st.max_angle == -kInf) {
    Fail(where, key + ".stops.max_deg = " + Deg(st.max_angle) +
                    ": must be finite (leave it out for no stop)");
  }
  if (!(st.min_angle < st.max_angle)) {
    Fail(where, key + ".stops.max_deg = " + Deg(st.max_angle) + ": must be > min_deg (" +
                    Deg(st.min_angle) + ")");
  }
  if (std::isfinite(st.min_angle)) {
    require.Range(".stops.min_deg", st.min_angle, kMaxDriveAngle, "deg", true);
  }
  if (std::isfinite(st.max_angle)) {
    require.Range(".stops.max_deg", st.max_angle, kMaxDriveAngle, "deg", true);
  }
  require(".stops.restitution", st.restitution, st.restitution >= 0.0 && st.restitution <= 1.0,
          "must be in [0, 1] (0: the hinge stops dead on a stop, 1: a lossless rebound)");
  if (st.restitution != 0.0 && !st.any()) {
    Fail(where, key + ".stops.restitution = " + Num(st.restitution) +
                    ": a restitution needs a stop (min_deg or max_deg) to rebound from");
  }
  if (theta0 < st.min_angle || theta0 > st.max_angle) {
    const bool below = theta0 < st.min_angle;
    Fail(where, key +
                    (below ? ".stops.min_deg = " + Deg(st.min_angle)
                           : ".stops.max_deg = " + Deg(st.max_angle)) +
                    ": the hinge's initial angle (" + InitialAngleText(p, theta0) +
                    ") must lie within the stops " + StopRange(st));
  }
}

/// The drive's latch: an angle within the stops that differs from the initial angle
/// theta0; a jam fraction in (0, 1), and only with a latch.
void ValidateLatch(
    const Profile& p, const DriveCheck& require, const Latch& la, const Stops& st, double theta0) {
  const std::string& where = require.where;
  const std::string& key = require.key;
  if (la.enabled) {
    require.Range(".latch.angle_deg", la.angle, kMaxDriveAngle, "deg", true);
    if (la.angle < st.min_angle || la.angle > st.max_angle) {
      Fail(where, key + ".latch.angle_deg = " + Deg(la.angle) +
                      ": the latch angle must lie within the stops " + StopRange(st));
    }
    if (la.angle == theta0) {
      Fail(where, key + ".latch.angle_deg = " + Deg(la.angle) +
                      ": the latch angle must differ from the hinge's initial angle (" +
                      InitialAngleText(p, theta0) + "): the hinge would latch before it moves");
    }
  }
  require(".latch.jam_fraction", la.jam_fraction,
          la.jam_fraction == 0.0 || (la.jam_fraction > 0.0 && la.jam_fraction < 1.0),
          "must be in (0, 1): the fraction of the swing from release to latch at which the "
          "hinge jams (leave it out for a latch that does not jam)");
  if (la.jam_fraction != 0.0 && !la.enabled) {
    Fail(where, key + ".latch.jam_fraction = " + Num(la.jam_fraction) +
                    ": a jam needs a latch (it is a fraction of the swing to the latch angle)");
  }
}

/// The release of free hinge k: at a time after start, or after the latch of another
/// panel's free hinge that has a latch.
void ValidateRelease(const Profile& p,
                     const DriveCheck& require,
                     std::size_t k,
                     const Release& re) {
  const std::string& where = require.where;
  const std::vector<model::Panel>& panels = p.model.hinged.panels;
  if (re.kind == Release::Kind::kAtTime) {
    require(".release.at", re.time, re.time >= p.start,
            "must be >= start (" + Num(p.start) +
                " s; leave release out for a hinge free from the start)");
  } else if (re.kind == Release::Kind::kAfterLatch) {
    const std::string rk = require.key + ".release.after_latch = ";
    if (re.panel < 0 || static_cast<std::size_t>(re.panel) >= panels.size()) {
      Fail(where, rk + std::to_string(re.panel) + ": no such panel (the model has " +
                      std::to_string(panels.size()) + " panels)");
    }
    const std::size_t j = static_cast<std::size_t>(re.panel);
    const std::string& other = panels[j].name;
    if (j == k) {
      Fail(where, rk + other +
                      ": a hinge cannot wait for its own latch (it is locked until "
                      "released, so it would never move)");
    }
    const HingePlan& waited = p.hinges[j];
    if (waited.kind != HingePlan::Kind::kFree) {
      Fail(where, rk + other + ": panel '" + other + "' is " + ToString(waited.kind) +
                      ": a release waits for a free hinge with a latch");
    }
    if (!waited.drive.latch.enabled) {
      Fail(where, rk + other + ": panel '" + other +
                      "' has no latch: it never latches, so this hinge would never be released");
    }
    require(".release.delay", re.delay, re.delay >= 0.0, "must be >= 0 [s]");
  }
}

/// The drive of free hinge k (key: "hinges.<panel>.free"), whose angle at start is theta0.
void ValidateDrive(const Profile& p,
                   const std::string& where,
                   const std::string& key,
                   std::size_t k,
                   double theta0) {
  const FreeDrive& d = p.hinges[k].drive;
  const DriveCheck require{where, key};
  const Spring& sp = d.spring;
  require(".spring.stiffness", sp.stiffness, sp.stiffness >= 0.0, "must be >= 0 [N m/rad]");
  require.Range(".spring.stiffness", sp.stiffness, kMaxDriveStiffness, "N m/rad");
  require.Range(".spring.rest_angle_deg", sp.rest_angle, kMaxDriveAngle, "deg", true);
  require.Range(".spring.preload", sp.preload, kMaxDriveTorque, "N m");
  require(".damper.coefficient", d.damping, d.damping >= 0.0, "must be >= 0 [N m s/rad]");
  require.Range(".damper.coefficient", d.damping, kMaxDriveDamping, "N m s/rad");

  ValidateMotor(p, require, d.motor);

  const Friction& fr = d.friction;
  require(".friction.torque", fr.torque, fr.torque >= 0.0, "must be >= 0 [N m] (0: no friction)");
  require.Range(".friction.torque", fr.torque, kMaxDriveTorque, "N m");
  require(".friction.regularization_speed_deg_s", fr.regularization_speed,
          fr.regularization_speed == 0.0 || fr.regularization_speed >= kMinRegularizationSpeed,
          "must be >= " + Deg(kMinRegularizationSpeed) +
              " deg/s (below it the regularized law tanh(rate / speed) makes the run stiff; "
              "leave it out for exact Coulomb friction, which sticks and slips)",
          true);

  ValidateStops(p, require, d.stops, theta0);
  ValidateLatch(p, require, d.latch, d.stops, theta0);
  ValidateRelease(p, require, k, d.release);
}

/// Releases that wait (after_latch) on each other in a cycle: none would ever move.
/// Each free hinge waits for at most one other, so following the waits from a panel either
/// ends (a hinge released otherwise) or comes back: within n steps.
void ValidateReleaseOrder(const Profile& p, const std::string& where) {
  const std::vector<model::Panel>& panels = p.model.hinged.panels;
  const std::size_t n = p.hinges.size();
  auto waits_for = [&](std::size_t k) -> int {
    const HingePlan& h = p.hinges[k];
    return h.kind == HingePlan::Kind::kFree && h.drive.release.kind == Release::Kind::kAfterLatch
               ? h.drive.release.panel
               : -1;
  };
  for (std::size_t k = 0; k < n; ++k) {
    int j = waits_for(k);
    std::size_t length = 1;
    while (j >= 0 && static_cast<std::size_t>(j) != k && length <= n) {
      j = waits_for(static_cast<std::size_t>(j));
      ++length;
    }
    if (j >= 0 && static_cast<std::size_t>(j) == k) {
      const std::string& next = panels[static_cast<std::size_t>(waits_for(k))].name;
      Fail(where, "hinges." + panels[k].name + ".free.release.after_latch = " + next +
                      ": the releases wait on each other in a cycle of " + std::to_string(length) +
                      " panels (back to '" + panels[k].name +
                      "'): none of them would ever be released");
    }
  }
}

/// One plan per panel; each plan's own rules, then the release order.
/// initial.hinge_rates_deg_s: one finite rate per panel, non-zero only where the hinge
/// moves freely from the start (a prescribed hinge's rate comes from its moves, a locked
/// or held one is at rest).
void ValidateInitialRates(const Profile& p, const std::string& where) {
  const Eigen::VectorXd& r = p.initial.hinge_rates;
  if (r.size() == 0) return;
  const std::vector<model::Panel>& panels = p.model.hinged.panels;
  if (r.size() != static_cast<Eigen::Index>(panels.size())) {
    Fail(where, "initial.hinge_rates_deg_s: " + std::to_string(r.size()) + " rates for " +
                    std::to_string(panels.size()) +
                    " panels (one per panel, in the model's order)");
  }
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const double rate = r[static_cast<Eigen::Index>(k)];
    const std::string key = "initial.hinge_rates_deg_s[" + std::to_string(k) + "] (" +
                            panels[k].name + ") = " + Deg(rate);
    if (!std::isfinite(rate)) Fail(where, key + ": must be finite");
    if (rate == 0.0) continue;
    const HingePlan& plan = p.hinges[k];
    const Release& rel = plan.drive.release;
    const bool from_start = rel.kind == Release::Kind::kAtStart ||
                            (rel.kind == Release::Kind::kAtTime && rel.time <= p.t_begin());
    if (plan.kind != HingePlan::Kind::kFree || !from_start) {
      Fail(where, key +
                      ": only a free hinge released at the start may move at `start` (a "
                      "prescribed hinge's rate comes from its moves; a locked or held one is "
                      "at rest)");
    }
  }
}

void ValidateHinges(const Profile& p, const std::string& where) {
  const std::vector<model::Panel>& panels = p.model.hinged.panels;
  if (p.hinges.size() != panels.size()) {
    Fail(where, "hinges: " + std::to_string(p.hinges.size()) + " plans for " +
                    std::to_string(panels.size()) +
                    " panels (one per panel, in the model's panel order)");
  }
  const Eigen::VectorXd& theta0 = FindConfiguration(p.model, p.initial.configuration)->hinge_angles;
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const HingePlan& plan = p.hinges[k];
    const std::string key = "hinges." + panels[k].name;
    if (plan.kind == HingePlan::Kind::kPrescribed) {
      ValidateMoves(p, where, key + ".prescribed", plan.moves);
    } else if (plan.kind == HingePlan::Kind::kFree) {
      ValidateDrive(p, where, key + ".free", k, theta0[static_cast<Eigen::Index>(k)]);
    }
  }
  ValidateReleaseOrder(p, where);
  ValidateInitialRates(p, where);
}

void ValidateNumerics(const Profile& p, const std::string& where) {
  const IntegratorSpec& s = p.integrator;
  auto require = [&](const std::string& key, double value, const std::string& rule) {
    if (!std::isfinite(value)) Fail(where, key + " = " + Num(value) + ": must be finite");
    if (!rule.empty()) Fail(where, key + " = " + Num(value) + ": " + rule);
  };
  for (const auto& [key, value] : {std::pair<std::string, double>{"rtol", s.rtol},
                                   {"atol", s.atol},
                                   {"step", s.step},
                                   {"max_step", s.max_step}}) {
    require("integrator." + key, value, IntegratorRuleViolated(key, value));
  }
  require("output.dt", p.output.dt, p.output.dt > 0.0 ? "" : "must be > 0");
}

}  // namespace

std::string IntegratorRuleViolated(const std::string& key, double value) {
  if (key == "rtol") {
    return value >= kMinRtol && value <= kMaxRtol
               ? ""
               : "must be in [" + Num(kMinRtol) + ", " + Num(kMaxRtol) + "]";
  }
  if (key == "atol") {
    return value > 0.0 && value <= kMaxAtol ? "" : "must be in (0, " + Num(kMaxAtol) + "]";
  }
  if (key == "step") return value >= 0.0 ? "" : "must be >= 0 (0: automatic)";
  if (key == "max_step") return value > 0.0 ? "" : "must be > 0";
  throw std::invalid_argument("IntegratorRuleViolated: no rule for integrator." + key);
}

std::string ToString(Mode m) {
  switch (m) {
    case Mode::kTensor:
      return "tensor";
    case Mode::kGeometry:
      return "geometry";
  }
  return "unknown";
}

std::string ToString(Coupling c) {
  switch (c) {
    case Coupling::kQuasiRigid:
      return "quasi-rigid";
    case Coupling::kExact:
      return "exact";
  }
  return "unknown";
}

namespace {
std::atomic<std::uint64_t> validations{0};
}  // namespace

std::uint64_t ValidationCount() { return validations.load(); }

void ValidateProfile(const Profile& p) {
  ++validations;
  const std::string where = p.source.empty() ? "profile '" + p.name + "'" : p.source;
  if (p.is_hinge_profile()) {
    ValidateHingeModes(p, where);
    ValidateModel(p, where);
    ValidateHingeRun(p, where);
    ValidateHinges(p, where);
  } else {
    ValidateModes(p, where);
    ValidateModel(p, where);
    ValidateStages(p, where);
    if (!p.initial.configuration.empty()) {
      Fail(where, "initial.configuration = '" + p.initial.configuration +
                      "': only in hinge profiles (a stage profile starts in the configuration "
                      "of its first stage)");
    }
  }
  ValidateInitial(p, where);
  ValidateNumerics(p, where);
}

void SetAppendagePlans(const model::Model& m, std::vector<HingePlan>& plans) {
  for (const model::Appendage& a : m.appendages) {
    for (std::size_t i = 0; i < a.hinges.size(); ++i) {
      HingePlan& plan = plans.at(static_cast<std::size_t>(a.hinges[i]));
      plan = HingePlan();
      plan.kind = HingePlan::Kind::kFree;
      plan.drive.spring.stiffness = a.stiffness[i];
      plan.drive.damping = a.damping[i];
    }
  }
}

}  // namespace deploysim::schedule
