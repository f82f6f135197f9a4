#include "deploysim/schedule/profile.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "deploysim/math/inertia.h"
#include "deploysim/math/number_format.h"
#include "deploysim/model/mass_properties.h"

namespace deploysim::schedule {

namespace {

/// The project's number formatting (math/number_format.h) under a short local name.
constexpr auto& Num = math::FormatNumber;

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
  if (in.w_NB_B.has_value() == in.H_B.has_value()) {
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

void ValidateNumerics(const Profile& p, const std::string& where) {
  const IntegratorSpec& s = p.integrator;
  auto require = [&](const std::string& key, double value, bool ok, const std::string& rule) {
    if (!std::isfinite(value)) Fail(where, key + " = " + Num(value) + ": must be finite");
    if (!ok) Fail(where, key + " = " + Num(value) + ": " + rule);
  };
  require("integrator.rtol", s.rtol, s.rtol >= 1e-16 && s.rtol < 1.0, "must be in [1e-16, 1)");
  require("integrator.atol", s.atol, s.atol > 0.0, "must be > 0");
  require("integrator.step", s.step, s.step >= 0.0, "must be >= 0 (0: automatic)");
  require("integrator.max_step", s.max_step, s.max_step > 0.0, "must be > 0");
  require("output.dt", p.output.dt, p.output.dt > 0.0, "must be > 0");
}

}  // namespace

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

void ValidateProfile(const Profile& p) {
  const std::string where = p.source.empty() ? "profile '" + p.name + "'" : p.source;
  ValidateModes(p, where);
  ValidateModel(p, where);
  ValidateStages(p, where);
  ValidateInitial(p, where);
  ValidateNumerics(p, where);
}

}  // namespace deploysim::schedule
