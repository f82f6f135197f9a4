#pragma once

/// Models and hinge profiles for the free-hinge tests, built in C++ (no YAML): the small
/// satellite of models/smallsat.yaml (keep the numbers in step) and its wings driven by
/// springs, dampers and latches.

#include <cmath>
#include <string>

#include "deploysim/model/mass_properties.h"
#include "deploysim/model/model.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::testing {

inline constexpr double kDeg = M_PI / 180.0;

/// The configuration "initial" of a hinged model, every hinge at 0 (one angle per panel),
/// as its only configuration.
inline void SetInitialConfiguration(model::Model& md) {
  model::Configuration c;
  c.name = "initial";
  c.hinge_angles = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(md.hinged.panels.size()));
  md.configurations = {c};
}

/// models/smallsat.yaml: 85 kg hub, two 6 kg wings hinged along y; closed 90 deg, open 0.
inline model::Model SmallsatModel() {
  model::Model m;
  m.name = "smallsat";
  m.kind = model::ModelKind::kHinged;
  m.hinged.hub.body.mass = 85.0;
  m.hinged.hub.body.inertia_cm = model::BoxInertia(85.0, math::Vec3(0.6, 1.0, 0.8));
  for (int side : {+1, -1}) {
    model::Panel p;
    p.name = side > 0 ? "wing_plus_x" : "wing_minus_x";
    p.body.mass = 6.0;
    p.body.inertia_cm = model::BoxInertia(6.0, math::Vec3(0.8, 1.0, 0.02));
    p.hinge_point_B = math::Vec3(0.3 * side, 0.0, 0.4 * side);
    p.hinge_axis_B = math::Vec3::UnitY();
    p.com_offset_B = math::Vec3(0.4 * side, 0.0, 0.01 * side);
    m.hinged.panels.push_back(p);
  }
  model::Configuration closed, open;
  closed.name = "closed";
  closed.hinge_angles = Eigen::Vector2d(90 * kDeg, 90 * kDeg);
  open.name = "open";
  open.hinge_angles = Eigen::Vector2d(0.0, 0.0);
  m.configurations = {closed, open};
  return m;
}

/// A free hinge with a torsion spring (and optionally a damper): no stops, no latch.
inline schedule::HingePlan SpringHinge(double stiffness, double rest_deg, double damping = 0.0) {
  schedule::HingePlan h;
  h.kind = schedule::HingePlan::Kind::kFree;
  h.drive.spring.stiffness = stiffness;
  h.drive.spring.rest_angle = rest_deg * kDeg;
  h.drive.damping = damping;
  return h;
}

/// The hinge profile of the small satellite spun at 5 rpm about y from its closed
/// configuration, both wings with the given plans, from 0 to `until`.
inline schedule::Profile SmallsatHingeProfile(const schedule::HingePlan& plus,
                                              const schedule::HingePlan& minus,
                                              double until) {
  schedule::Profile p;
  p.name = "smallsat_free";
  p.source = "smallsat_free (test)";
  p.model = SmallsatModel();
  p.mode = schedule::Mode::kGeometry;
  p.coupling = schedule::Coupling::kExact;
  p.initial.configuration = "closed";
  p.initial.w_NB_B = math::Vec3(0.0091, 0.5235988, 0.0091);
  p.hinges = {plus, minus};
  p.start = 0.0;
  p.until = until;
  p.integrator.method = "rkmk-rkf78";
  p.integrator.rtol = 1e-12;
  p.integrator.atol = 1e-14;
  p.output.dt = 0.1;
  return p;
}

}  // namespace deploysim::testing
