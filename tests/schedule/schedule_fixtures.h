#pragma once

/// Models and profiles for the schedule tests, built in C++ (no YAML).

#include <cmath>
#include <string>
#include <vector>

#include "deploysim/math/so3.h"
#include "deploysim/math/types.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/model/model.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::schedule::testing {

constexpr double kPi = 3.14159265358979323846;

inline model::Configuration TensorConfiguration(const std::string& name, const math::Mat3& J_B) {
  model::Configuration c;
  c.name = name;
  c.J_B = J_B;
  return c;
}

/// The seed thesis's satellite (section 3.4) as three tensors [kg m^2], spin about y:
/// closed J1 > J3 > J2, half-open J3 = J2, open J1 > J2 > J3 (the open tensor is a full
/// matrix, principal axes turned about z, so the interpolation sees products of inertia).
inline model::Model TensorModel() {
  model::Model m;
  m.name = "three_tensors";
  m.source = "models/three_tensors.yaml";
  m.kind = model::ModelKind::kTensors;
  const math::Mat3 R = math::ExpSO3(math::Vec3(0.0, 0.0, 0.3));
  const math::Mat3 open = R * math::Vec3(10.0, 8.0, 6.5).asDiagonal() * R.transpose();
  m.configurations = {
      TensorConfiguration("closed", math::Vec3(10.0, 6.0, 8.0).asDiagonal()),
      TensorConfiguration("half_open", math::Vec3(10.0, 7.0, 7.0).asDiagonal()),
      TensorConfiguration("open", 0.5 * (open + open.transpose())),
  };
  return m;
}

inline model::Configuration HingeConfiguration(const std::string& name, double a0, double a1) {
  model::Configuration c;
  c.name = name;
  c.hinge_angles = Eigen::Vector2d(a0, a1);
  return c;
}

/// A hub with two unequal panels (so the system CoM moves as they turn); one hinge axis
/// is tilted out of the y axis. Configurations are hinge angles [rad].
inline model::Model HingedModel() {
  model::Model m;
  m.name = "smallsat";
  m.source = "models/smallsat.yaml";
  m.kind = model::ModelKind::kHinged;
  m.hinged.hub.body.mass = 80.0;
  m.hinged.hub.body.inertia_cm = model::BoxInertia(80.0, math::Vec3(0.6, 0.6, 0.8));
  m.hinged.hub.com_B = math::Vec3(0.01, 0.0, 0.02);
  model::Panel p0;
  p0.name = "wing_plus_x";
  p0.body.mass = 6.0;
  p0.body.inertia_cm = model::BoxInertia(6.0, math::Vec3(1.0, 0.02, 0.7));
  p0.hinge_point_B = math::Vec3(0.3, 0.0, 0.0);
  p0.hinge_axis_B = math::Vec3(0.0, 1.0, 0.0);
  p0.com_offset_B = math::Vec3(0.5, 0.0, 0.0);
  model::Panel p1;
  p1.name = "wing_minus_x";
  p1.body.mass = 4.0;
  p1.body.inertia_cm = model::BoxInertia(4.0, math::Vec3(0.8, 0.02, 0.6));
  p1.hinge_point_B = math::Vec3(-0.3, 0.0, 0.05);
  p1.hinge_axis_B = math::Vec3(0.0, 1.0, 0.2).normalized();
  p1.com_offset_B = math::Vec3(-0.4, 0.0, 0.0);
  m.hinged.panels = {p0, p1};
  m.configurations = {
      HingeConfiguration("closed", -kPi / 2.0, kPi / 2.0),
      HingeConfiguration("half_open", -kPi / 4.0, kPi / 4.0),
      HingeConfiguration("open", 0.0, 0.0),
  };
  return m;
}

inline Stage Hold(const std::string& config, double t_begin, double t_end) {
  Stage s;
  s.name = "hold " + config;
  s.from = config;
  s.to = config;
  s.t_begin = t_begin;
  s.t_end = t_end;
  return s;
}

inline Stage Move(
    const std::string& from, const std::string& to, Law law, double t_begin, double t_end) {
  Stage s;
  s.name = "to " + to;
  s.from = from;
  s.to = to;
  s.law = law;
  s.t_begin = t_begin;
  s.t_end = t_end;
  return s;
}

/// Five stages: hold closed [0, 10], move to half_open [10, 25], hold [25, 30],
/// move to open [30, 50], hold open [50, 60]. Both moves use `law`.
inline Profile MakeProfile(const model::Model& m, Mode mode, Coupling coupling, Law law) {
  Profile p;
  p.name = "three_stage";
  p.source = "p.yaml";
  p.model = m;
  p.mode = mode;
  p.coupling = coupling;
  p.initial.w_NB_B = math::Vec3(0.001, 0.5, 0.001);
  p.stages = {
      Hold("closed", 0.0, 10.0),     Move("closed", "half_open", law, 10.0, 25.0),
      Hold("half_open", 25.0, 30.0), Move("half_open", "open", law, 30.0, 50.0),
      Hold("open", 50.0, 60.0),
  };
  return p;
}

/// Times strictly inside the two moving stages of MakeProfile.
inline std::vector<double> MovingTimes() {
  return {10.3, 12.0, 17.5, 21.0, 24.7, 30.4, 36.0, 40.0, 44.4, 49.6};
}

}  // namespace deploysim::schedule::testing
