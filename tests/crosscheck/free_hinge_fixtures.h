#pragma once

/// Hub + panel models and hinge profiles for the free-hinge cross-check tests, built in C++
/// (no YAML): the small satellite of models/smallsat.yaml, a two-segment chain and a
/// branched tree with skew hinge axes, a pendulum-damper spinner, flexible booms
/// and a propellant tank's slosh pendulum on spinners.

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "deploysim/math/types.h"
#include "deploysim/model/flexible_beam.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/model/model.h"
#include "deploysim/model/slosh.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::crosscheck::free_hinge_fixtures {

using schedule::HingePlan;

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDeg = kPi / 180.0;

inline model::Panel MakePanel(const std::string& name,
                              int parent,
                              const math::Vec3& hinge_point,
                              const math::Vec3& axis,
                              const math::Vec3& com_offset,
                              double mass,
                              const math::Vec3& box) {
  model::Panel p;
  p.name = name;
  p.parent = parent;
  p.body.mass = mass;
  p.body.inertia_cm = model::BoxInertia(mass, box);
  p.hinge_point_B = hinge_point;
  p.hinge_axis_B = axis.normalized();
  p.com_offset_B = com_offset;
  return p;
}

/// A hinged model whose only configuration, "initial", has the hinge angles `angles0`.
inline model::Model MakeModel(const std::string& name,
                              double hub_mass,
                              const math::Vec3& hub_box,
                              std::vector<model::Panel> panels,
                              const Eigen::VectorXd& angles0) {
  model::Model m;
  m.name = name;
  m.source = name + " (C++)";
  m.kind = model::ModelKind::kHinged;
  m.hinged.hub.body.mass = hub_mass;
  m.hinged.hub.body.inertia_cm = model::BoxInertia(hub_mass, hub_box);
  m.hinged.panels = std::move(panels);
  model::Configuration c;
  c.name = "initial";
  c.hinge_angles = angles0;
  m.configurations.push_back(c);
  return m;
}

/// The small satellite of models/smallsat.yaml (85 kg hub, two 6 kg wings hinged about y,
/// theta = 90 deg stowed, 0 deployed), at `angle` (default stowed).
inline model::Model SmallSat(double angle = 90 * kDeg) {
  const math::Vec3 wing(0.8, 1.0, 0.02);
  return MakeModel("smallsat", 85.0, math::Vec3(0.6, 1.0, 0.8),
                   {MakePanel("wing_plus_x", -1, math::Vec3(0.3, 0, 0.4), math::Vec3::UnitY(),
                              math::Vec3(0.4, 0, 0.01), 6.0, wing),
                    MakePanel("wing_minus_x", -1, math::Vec3(-0.3, 0, -0.4), math::Vec3::UnitY(),
                              math::Vec3(-0.4, 0, -0.01), 6.0, wing)},
                   Eigen::Vector2d(angle, angle));
}

/// Spin about the small satellite's y axis (5 rpm) with a small nutation [rad/s].
inline math::Vec3 SmallSatSpin() { return math::Vec3(0.0091, 0.5235988, 0.0091); }

inline schedule::Profile HingeProfile(const model::Model& m,
                                      std::vector<HingePlan> plans,
                                      const math::Vec3& w0_B,
                                      double until) {
  schedule::Profile p;
  p.name = m.name + "_test";
  p.source = p.name + " (C++)";
  p.model = m;
  p.mode = schedule::Mode::kGeometry;
  p.coupling = schedule::Coupling::kExact;
  p.initial.configuration = "initial";
  p.initial.w_NB_B = w0_B;
  p.hinges = std::move(plans);
  p.start = 0.0;
  p.until = until;
  return p;
}

inline HingePlan Locked() { return HingePlan{}; }

inline HingePlan Free(double stiffness, double rest_angle, double damping = 0.0) {
  HingePlan h;
  h.kind = HingePlan::Kind::kFree;
  h.drive.spring.stiffness = stiffness;
  h.drive.spring.rest_angle = rest_angle;
  h.drive.damping = damping;
  return h;
}

inline HingePlan WithLatch(HingePlan h, double angle, double jam_fraction = 0.0) {
  h.drive.latch.enabled = true;
  h.drive.latch.angle = angle;
  h.drive.latch.jam_fraction = jam_fraction;
  return h;
}

inline std::vector<double> Grid(double t0, double t1, double dt) {
  std::vector<double> g;
  const long n = std::lround((t1 - t0) / dt);
  for (long i = 0; i <= n; ++i) g.push_back(t0 + static_cast<double>(i) * dt);
  return g;
}

/// A two-segment chain with skew hinge axes (a child's axis in its parent's axes): panel A
/// on the hub, panel B on A's far edge, folded, both spring-driven to latches.
inline model::Model SkewChain() {
  const math::Vec3 plate(0.8, 1.0, 0.02);
  Eigen::VectorXd angles0(2);
  angles0 << 80 * kDeg, -120 * kDeg;
  return MakeModel("skew_chain", 85.0, math::Vec3(0.6, 1.0, 0.8),
                   {MakePanel("segment_a", -1, math::Vec3(0.3, 0, 0.4), math::Vec3(0, 1, 0.25),
                              math::Vec3(0.4, 0, 0.01), 5.0, plate),
                    MakePanel("segment_b", 0, math::Vec3(0.8, 0, 0), math::Vec3(0.2, 1, 0),
                              math::Vec3(0.4, 0, -0.01), 4.0, plate)},
                   angles0);
}

/// A branched tree with skew axes, listed child first: panels[1] (root) on the hub,
/// panels[0] and panels[2] on panels[1]'s far edge and on its side.
inline model::Model SkewTree() {
  const math::Vec3 plate(0.8, 1.0, 0.02);
  Eigen::VectorXd angles0(3);
  angles0 << -120 * kDeg, 80 * kDeg, 60 * kDeg;
  return MakeModel("skew_tree", 85.0, math::Vec3(0.6, 1.0, 0.8),
                   {MakePanel("tip", 1, math::Vec3(0.8, 0, 0), math::Vec3(0.2, 1, 0),
                              math::Vec3(0.4, 0, -0.01), 4.0, plate),
                    MakePanel("root", -1, math::Vec3(0.3, 0, 0.4), math::Vec3(0, 1, 0.25),
                              math::Vec3(0.4, 0, 0.01), 5.0, plate),
                    MakePanel("side", 1, math::Vec3(0.4, 0.5, 0), math::Vec3(1, 0, 0.3),
                              math::Vec3(0, 0.3, 0), 2.0, math::Vec3(0.6, 0.6, 0.02))},
                   angles0);
}

/// A minor-axis spinner: a 30 kg hub long along z spinning about z, with a pendulum damper
/// (a 10 kg block on an arm hinged about y at the +x face, soft spring, damper).
inline model::Model PendulumDamperSpinner() {
  return MakeModel("pendulum_damper", 30.0, math::Vec3(0.6, 0.8, 1.6),
                   {MakePanel("damper", -1, math::Vec3(0.3, 0, 0), math::Vec3::UnitY(),
                              math::Vec3(0.5, 0, 0), 10.0, math::Vec3(0.1, 0.1, 0.1))},
                   Eigen::VectorXd::Zero(1));
}

/// A 60 kg hub (0.8 x 0.8 x 0.6 m) with two flexible booms (model/flexible_beam.h) along
/// +-x: +x bends in two planes (EI 20 and 30 N m^2, massless links), -x in one (about y,
/// EI 20). 2 m long, 0.2 kg/m, `segments` segments each, damping ratio `zeta`; every
/// bending hinge straight ("initial").
inline model::Model BoomSpinner(int segments, double zeta) {
  model::Model m =
      MakeModel("boom_spinner", 60.0, math::Vec3(0.8, 0.8, 0.6), {}, Eigen::VectorXd());
  for (int side : {+1, -1}) {
    model::BeamSpec s;
    s.name = side > 0 ? "boom_px" : "boom_mx";
    s.root_point = math::Vec3(0.4 * side, 0.0, 0.05);
    s.direction = math::Vec3(side, 0.0, 0.0);
    s.length = 2.0;
    s.mass_per_length = 0.2;
    s.radius = 0.01;
    s.planes = {model::BeamPlane{math::Vec3::UnitY(), 20.0}};
    if (side > 0) s.planes.push_back(model::BeamPlane{math::Vec3::UnitZ(), 30.0});
    s.damping_ratio = zeta;
    s.segments = segments;
    m.appendages.push_back(model::AddBeam(m.hinged, s, "boom_spinner"));
  }
  m.configurations[0].hinge_angles =
      Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m.hinged.panels.size()));
  return m;
}

/// The plans of a model with appendages: its bending hinges free on their springs and
/// dampers (schedule::SetAppendagePlans), every other hinge locked.
inline std::vector<HingePlan> AppendagePlans(const model::Model& m) {
  std::vector<HingePlan> plans(m.hinged.panels.size());
  schedule::SetAppendagePlans(m, plans);
  return plans;
}

/// A prolate spinner with a propellant tank (model/slosh.h): a 300 kg hub, 1 x 1 x 2 m
/// (moments 125, 125, 50 kg m^2: z, the long axis, is its minor axis), with a tank 0.5 m
/// off the axis along +x and 0.2 m above the middle: 30 kg of liquid fixed with the tank
/// at 0.55 m, and a slosh pendulum (20 kg bob, L1 = 0.15 m, hanging outward along +x, the
/// first hinge about z) with the damper `damping` [N m s/rad] on both hinges.
inline model::Model SloshSpinner(double damping) {
  model::Model m =
      MakeModel("slosh_spinner", 300.0, math::Vec3(1.0, 1.0, 2.0), {}, Eigen::VectorXd());
  model::SloshSpec s;
  s.name = "tank";
  s.pivot = math::Vec3(0.5, 0.0, 0.2);
  s.direction = math::Vec3::UnitX();
  s.axis = math::Vec3::UnitZ();
  s.mass = 20.0;
  s.length = 0.15;
  s.fixed_mass = 30.0;
  s.fixed_point = math::Vec3(0.55, 0.0, 0.2);
  s.damping = damping;
  m.appendages.push_back(model::AddSlosh(m.hinged, s, "slosh_spinner"));
  m.configurations[0].hinge_angles =
      Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m.hinged.panels.size()));
  return m;
}

/// Spin about the slosh spinner's z axis at 3 rad/s (29 rpm) with 2 deg of nutation.
inline math::Vec3 SloshSpinnerSpin() { return math::Vec3(3.0 * std::tan(2 * kDeg), 0.0, 3.0); }

}  // namespace deploysim::crosscheck::free_hinge_fixtures
