// The slosh spinner of free_hinge_fixtures.h (SloshSpinner: a 300 kg prolate hub, a tank
// 0.5 m off its minor spin axis with 30 kg of fixed liquid and a 20 kg, 0.15 m slosh
// pendulum) against Simbody models built here from the tank's numbers alone: none of
// model/slosh.h's panels, the project's generic Simbody model or its composite masses.
//   - The pendulum on a MobilizedBody::Universal (rotation about F's x, then about the new
//     y: F's x the first hinge axis z, F's y = direction x axis, F's z the rest direction),
//     its bob a point mass, a MobilityLinearDamper on each of its two speeds; the fixed
//     liquid a point mass welded to the hub. A Ball or Gimbal cannot carry the bob: a point
//     mass has no inertia about its arm, so a third rotation has a singular mass matrix;
//     the Universal is the spherical pendulum's two degrees of freedom.
//   - Undamped, the bob as a free particle (MobilizedBody::Translation on the hub)
//     held at L1 from the pivot by a Constraint::Rod: no angles at all, the pendulum's
//     angles recovered from the bob's position.
// Compared on a 1 s grid: H_B / |H_B(t0)|, the attitude [rad] and the two hinge angles
// [rad].

#include <Simbody.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "crosscheck/free_hinge_fixtures.h"
#include "deploysim/run/mission.h"

namespace deploysim::crosscheck {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using namespace free_hinge_fixtures;  // NOLINT: the shared test builders
using math::Mat3;
using math::Vec3;

// The spinner's numbers (free_hinge_fixtures.h SloshSpinner), repeated: this model is
// built from them, not from the fixture's panels.
constexpr double kHubMass = 300.0;               // [kg], a 1 x 1 x 2 m box, CoM at B's origin
constexpr double kLiquidMass = 30.0;             // [kg] m0
const SimTK::Vec3 kLiquidPoint(0.55, 0.0, 0.2);  // [m]
constexpr double kBobMass = 20.0;                // [kg] m1
constexpr double kArm = 0.15;                    // [m] L1
const SimTK::Vec3 kPivot(0.5, 0.0, 0.2);         // [m]; rest direction +x, first axis z

enum class Pendulum { kUniversal, kRod };

struct Samples {
  std::vector<Vec3> H_B;
  std::vector<Mat3> R_NB;
  std::vector<Eigen::Vector2d> angles;  // [rad] the first and the second hinge's
  double wall_seconds = 0.0;
};

Mat3 ToEigen(const SimTK::Mat33& m) {
  Mat3 r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r(i, j) = m(i, j);
  }
  return r;
}

/// The hinge angles of a bob at unit direction u (hub axes) from the pivot: u =
/// Rot(z, t1) Rot(-y, t2) x = (cos t2 cos t1, cos t2 sin t1, sin t2).
Eigen::Vector2d AnglesOf(const SimTK::Vec3& u) {
  return Eigen::Vector2d(std::atan2(u[1], u[0]), std::asin(std::clamp(u[2], -1.0, 1.0)));
}

/// Runs the Simbody spinner from the identity attitude with hub angular velocity w0
/// (B components), the pendulum at rest relative to the hub, zero linear momentum;
/// samples at `grid`.
Samples RunSimbody(Pendulum kind,
                   double damping,
                   const Vec3& w0,
                   const std::vector<double>& grid,
                   double accuracy) {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter(system);
  SimTK::GeneralForceSubsystem forces(system);
  const double m = kHubMass;  // box 1 x 1 x 2 m
  const SimTK::Inertia box(m / 12 * (1 + 4), m / 12 * (1 + 4), m / 12 * (1 + 1));
  SimTK::MobilizedBody::Free hub(matter.Ground(), SimTK::Transform(),
                                 SimTK::Body::Rigid(SimTK::MassProperties(m, SimTK::Vec3(0), box)),
                                 SimTK::Transform());
  const SimTK::Body::Rigid point_liquid(
      SimTK::MassProperties(kLiquidMass, SimTK::Vec3(0), SimTK::Inertia(0)));
  SimTK::MobilizedBody::Weld liquid(hub, SimTK::Transform(kLiquidPoint), point_liquid,
                                    SimTK::Transform());
  const SimTK::Vec3 arm(0, 0, kArm);  // the bob in the Universal's M frame (z: the rest direction)
  const SimTK::Body::Rigid bob(
      SimTK::MassProperties(kBobMass, arm, SimTK::Inertia::pointMassAt(arm, kBobMass)));
  // F: x = the first hinge axis (hub z), y = direction x axis (-y), z = direction (+x).
  const SimTK::Rotation R_HF(SimTK::Mat33(0, 0, 1, 0, -1, 0, 1, 0, 0));
  SimTK::MobilizedBody::Universal universal;
  SimTK::MobilizedBody::Translation particle;
  if (kind == Pendulum::kUniversal) {
    universal = SimTK::MobilizedBody::Universal(hub, SimTK::Transform(R_HF, kPivot), bob,
                                                SimTK::Transform());
    for (int u = 0; u < 2; ++u) {
      SimTK::Force::MobilityLinearDamper(forces, universal, SimTK::MobilizerUIndex(u), damping);
    }
  } else {
    const SimTK::Body::Rigid point_bob(
        SimTK::MassProperties(kBobMass, SimTK::Vec3(0), SimTK::Inertia(0)));
    particle = SimTK::MobilizedBody::Translation(hub, SimTK::Transform(kPivot), point_bob,
                                                 SimTK::Transform());
    SimTK::Constraint::Rod(hub, kPivot, particle, SimTK::Vec3(0), kArm);
  }
  SimTK::State s = system.realizeTopology();
  if (kind == Pendulum::kRod) particle.setQToFitTranslation(s, SimTK::Vec3(kArm, 0, 0));
  system.realize(s, SimTK::Stage::Position);
  const SimTK::Vec3 c = matter.calcSystemMassCenterLocationInGround(s);
  const SimTK::Vec3 w(w0[0], w0[1], w0[2]);
  hub.setUToFitAngularVelocity(s, w);
  hub.setUToFitLinearVelocity(s, -w % c);  // the system's CoM at rest
  SimTK::RungeKuttaMersonIntegrator integ(system);
  integ.setAccuracy(accuracy);
  integ.setConstraintTolerance(accuracy);
  integ.initialize(s);
  Samples out;
  const auto t0 = std::chrono::steady_clock::now();
  for (double t : grid) {
    // The first stepTo returns at the start of the interval (t0): step until t.
    while (integ.getTime() < t) integ.stepTo(t, t);
    const SimTK::State& st = integ.getState();
    system.realize(st, SimTK::Stage::Velocity);
    const Mat3 R = ToEigen(hub.getBodyRotation(st).asMat33());
    const SimTK::Vec3 h = matter.calcSystemCentralMomentum(st)[0];
    out.R_NB.push_back(R);
    out.H_B.push_back(R.transpose() * Vec3(h[0], h[1], h[2]));
    if (kind == Pendulum::kUniversal) {
      out.angles.emplace_back(universal.getOneQ(st, 0), universal.getOneQ(st, 1));
    } else {
      const SimTK::Vec3 p(particle.getOneQ(st, 0), particle.getOneQ(st, 1),
                          particle.getOneQ(st, 2));
      out.angles.push_back(AnglesOf(p / p.norm()));
    }
  }
  out.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

struct Difference {
  double H_B = 0.0;       // max |dH_B| / |H_B(t0)|
  double attitude = 0.0;  // [rad]
  double angles = 0.0;    // [rad]
};

Difference Compare(const Samples& a, const Samples& b) {
  Difference d;
  const double H0 = b.H_B.front().norm();
  for (std::size_t i = 0; i < b.H_B.size(); ++i) {
    d.H_B = std::max(d.H_B, (a.H_B[i] - b.H_B[i]).norm() / H0);
    // The rotation angle of R_a^T R_b: 2 asin(|R_a - R_b|_F / sqrt(8)).
    d.attitude =
        std::max(d.attitude,
                 2.0 * std::asin(std::min(1.0, (a.R_NB[i] - b.R_NB[i]).norm() / std::sqrt(8.0))));
    d.angles = std::max(d.angles, (a.angles[i] - b.angles[i]).cwiseAbs().maxCoeff());
  }
  return d;
}

/// The reduced model's run of the fixture (rkmk-rkf78 at rtol 1e-13), sampled on `grid`.
Samples RunReduced(double damping, const Vec3& w0, double until) {
  const model::Model m = SloshSpinner(damping);
  schedule::Profile p = HingeProfile(m, AppendagePlans(m), w0, until);
  p.integrator.method = "rkmk-rkf78";
  p.integrator.rtol = 1e-13;
  p.integrator.atol = 1e-15;
  p.output.dt = 1.0;
  const run::MissionResult r = run::RunMission(p);
  EXPECT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
  Samples out;
  for (std::size_t i = 0; i < r.trajectory.size(); ++i) {
    out.H_B.push_back(r.trajectory.H_B[i]);
    out.R_NB.push_back(r.trajectory.q_NB[i].toRotationMatrix());
    const Eigen::VectorXd& th = r.trajectory.hinge_angles[i];
    out.angles.emplace_back(th[0], th[1]);
  }
  out.wall_seconds = r.wall_seconds;
  return out;
}

// Damped (2 N m s/rad), 60 s: the slosh raises the nutation (H_B from 0.6 deg off body z
// to 11 deg), the pendulum swings up to 9.5 deg. Measured against the Universal model at
// 1e-14: H_B 2.8e-14, attitude 5.0e-13 rad, angles 1.6e-14 rad (Simbody's own error, 1e-12
// against 1e-14: 7.9e-14, 1.4e-11, 1.2e-13). Bounds a few times above.
TEST(SloshSimbodyTest, DampedPendulumOnAUniversalJoint) {
  const double until = 60.0;
  const std::vector<double> grid = Grid(0.0, until, 1.0);
  const Samples reduced = RunReduced(2.0, SloshSpinnerSpin(), until);
  const Samples tight = RunSimbody(Pendulum::kUniversal, 2.0, SloshSpinnerSpin(), grid, 1e-14);
  const Samples loose = RunSimbody(Pendulum::kUniversal, 2.0, SloshSpinnerSpin(), grid, 1e-12);
  ASSERT_EQ(reduced.H_B.size(), grid.size());
  const Difference d = Compare(reduced, tight);
  const Difference own = Compare(loose, tight);
  double swing = 0.0, tilt = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    swing = std::max(swing, tight.angles[i].cwiseAbs().maxCoeff());
    const Vec3 H = tight.H_B[i].normalized();
    tilt = std::max(tilt, std::acos(std::clamp(H.z(), -1.0, 1.0)));
  }
  std::printf(
      "Universal, damped, %.0f s: H_B %.2e (Simbody 1e-12 vs 1e-14: %.2e), attitude %.2e rad "
      "(%.2e), angles %.2e rad (%.2e); largest swing %.1f deg, H from body z up to %.1f deg; "
      "reduced %.2f s, Simbody %.2f s\n",
      until, d.H_B, own.H_B, d.attitude, own.attitude, d.angles, own.angles, swing / kDeg,
      tilt / kDeg, reduced.wall_seconds, tight.wall_seconds);
  EXPECT_LE(d.H_B, 3e-13);
  EXPECT_LE(d.attitude, 3e-12);
  EXPECT_LE(d.angles, 1e-13);
  EXPECT_GT(tilt, 8 * kDeg);  // the energy sink at work: H_B leaves the minor axis z
}

// Undamped, 40 s: the particle on a rod (the pendulum swings up to 9.1 deg). Measured: H_B
// 5.2e-14, attitude 7.3e-13 rad, angles 3.4e-12 rad (Simbody's own error, 1e-12 against
// 1e-14: 4.0e-12, 5.7e-11, 2.5e-10: the rod's constraint projection). Bounds a few times
// above.
TEST(SloshSimbodyTest, UndampedPendulumAsAParticleOnARod) {
  const double until = 40.0;
  const std::vector<double> grid = Grid(0.0, until, 1.0);
  const Samples reduced = RunReduced(0.0, SloshSpinnerSpin(), until);
  const Samples tight = RunSimbody(Pendulum::kRod, 0.0, SloshSpinnerSpin(), grid, 1e-14);
  const Samples loose = RunSimbody(Pendulum::kRod, 0.0, SloshSpinnerSpin(), grid, 1e-12);
  const Difference d = Compare(reduced, tight);
  const Difference own = Compare(loose, tight);
  double swing = 0.0;
  for (const Eigen::Vector2d& a : tight.angles) swing = std::max(swing, a.cwiseAbs().maxCoeff());
  std::printf(
      "rod, undamped, %.0f s: H_B %.2e (Simbody 1e-12 vs 1e-14: %.2e), attitude %.2e rad "
      "(%.2e), angles %.2e rad (%.2e); largest swing %.2f deg; reduced %.2f s, Simbody %.2f s\n",
      until, d.H_B, own.H_B, d.attitude, own.attitude, d.angles, own.angles, swing / kDeg,
      reduced.wall_seconds, tight.wall_seconds);
  EXPECT_LE(d.H_B, 3e-13);
  EXPECT_LE(d.attitude, 3e-12);
  EXPECT_LE(d.angles, 1e-11);
  EXPECT_GT(swing, 5 * kDeg);  // the nutation moves the pendulum
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::crosscheck
