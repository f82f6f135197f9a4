// The lean per-case outcome (sweep/outcome.h) against the full mission run and against
// the closed-form torque-free solution.

#include "deploysim/sweep/outcome.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/analysis/mission.h"
#include "deploysim/math/inertia.h"
#include "deploysim/sweep/sweep_file.h"
#include "sweep_test_support.h"

namespace deploysim::sweep {
namespace {

using testing::SmallsatProfile;
using testing::SweepDirTest;

constexpr double kFlipTimeTolerance = 1e-9;    // [s] same steps, same event search
constexpr double kSameStateTolerance = 1e-12;  // relative: the same final state
constexpr double kMissionSampling = 0.01;      // [s] output grid of the reference run
// The reference samples the angle every 10 ms; the lean path finds the extrema between
// steps. Samples can miss a maximum by ~ (rate * dt)^2: far below this.
constexpr double kMaxAngleSampling = 2e-4;  // [rad]
constexpr double kConeTolerance = 1e-6;     // [rad] brute-force sampling of a period

TEST_F(SweepDirTest, LeanOutcomeAgreesWithTheMissionRun) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", "name: t\nbase: " + SmallsatProfile() + R"(
integrator: {method: exact, rtol: 1.0e-9, atol: 1.0e-11}
grid:
  - {parameter: deploy_duration_scale, values: [0.3, 2.5]}
  - {parameter: spin_rate_rpm, values: [3, 8]}
  - {parameter: law, values: [linear, minimum-jerk]}
  - {parameter: coupling, values: [exact, quasi-rigid]}
)"));
  // A spread of cases (of 16): both laws, both couplings, slow and fast.
  for (const std::size_t i : {0u, 5u, 10u, 15u}) {
    const Case c = BuildCase(spec, i);
    const CaseOutcome o = SimulateOutcome(c, spec.outcome);
    schedule::Profile p = c.profile;
    p.output.dt = kMissionSampling;
    const analysis::MissionResult m = analysis::RunMission(p);
    SCOPED_TRACE("case " + std::to_string(i) + " " + DescribeParameters(spec, c.parameters));
    ASSERT_EQ(o.termination, integrators::Termination::kReachedEnd);
    ASSERT_EQ(static_cast<std::size_t>(o.flip_count), m.flip_times.size());
    if (!m.flip_times.empty()) {
      EXPECT_NEAR(o.first_flip_time, m.flip_times[0], kFlipTimeTolerance);
    }
    EXPECT_EQ(c.spin_axis_B, m.spin_axis_B);
    const analysis::Trajectory& tr = m.trajectory;
    const double sampled_max =
        *std::max_element(tr.spin_axis_angle.begin(), tr.spin_axis_angle.end());
    EXPECT_GE(o.max_spin_axis_angle, sampled_max - 1e-9);
    EXPECT_LE(o.max_spin_axis_angle, sampled_max + kMaxAngleSampling);
    EXPECT_NEAR(o.final_spin_axis_angle, tr.spin_axis_angle.back(), 1e-9);
    EXPECT_NEAR(o.energy_final, tr.energy.back(), kSameStateTolerance * tr.energy.back());
    EXPECT_NEAR(o.energy_initial, tr.energy.front(), kSameStateTolerance * tr.energy.front());
    EXPECT_EQ(o.end_time, p.t_end());
    EXPECT_GT(o.run_time, 0.0);
  }
}

/// A rigid body (principal moments 1, 2, 3 kg m^2 along x, y, z) spinning at 1 rad/s
/// about `axis` for 20 s, swept over the nutation.
std::string RigidSweep(const SweepDirTest& t, const std::string& w, const std::string& grid) {
  t.Write("rigid_model.yaml",
          "name: rigid\nkind: tensors\nconfigurations:\n  body: {principal_moments: [1.0, 2.0, "
          "3.0]}\n");
  t.Write("rigid.yaml",
          "name: rigid\nmodel: rigid_model.yaml\ninitial: {angular_velocity: " + w +
              "}\nstages:\n  - {hold: body, until: 20}\nintegrator: {method: exact}\n");
  return t.Write("s.yaml",
                 "name: r\nbase: rigid.yaml\noutcome: {tumble_angle_deg: 20}\ngrid:\n" + grid);
}

/// Largest half-angle of the momentum cone about principal axis `axis`, and the largest
/// angle from `s` over [0, t_end], by sampling the closed-form solution densely.
struct BruteForce {
  double cone = 0.0;
  double max_angle = 0.0;
};
BruteForce Sample(const math::Vec3& H0, int axis, const math::Vec3& s, double t_end) {
  const analysis::FreeBodySolution sol(
      math::InertiaTensor::FromPrincipalMoments(math::Vec3(1.0, 2.0, 3.0)), H0);
  const double M = H0.norm();
  BruteForce b;
  const double period = std::isfinite(sol.period()) ? sol.period() : t_end;
  const int n = 20000;
  double min_axis = 1.0, min_s = 1.0;
  for (int k = 0; k <= n; ++k) {
    const math::Vec3 H = sol.H_B(period * k / n);
    min_axis = std::min(min_axis, std::abs(H[axis]) / M);
  }
  for (int k = 0; k <= n; ++k) min_s = std::min(min_s, s.dot(sol.H_B(t_end * k / n)) / M);
  b.cone = std::acos(min_axis);
  b.max_angle = std::acos(min_s);
  return b;
}

TEST_F(SweepDirTest, FinalMotionOfRigidBodies) {
  // Spin about the minor axis x, tilted towards y (azimuth 0) or z (azimuth 90).
  const SweepSpec minor =
      LoadSweep(RigidSweep(*this, "[1, 0, 0]",
                           "  - {parameter: nutation_deg, values: [0, 5, 15, 40]}\n"
                           "  - {parameter: nutation_azimuth_deg, values: [0, 90]}\n"));
  for (std::size_t i = 0; i < minor.case_count(); ++i) {
    const Case c = BuildCase(minor, i);
    const CaseOutcome o = SimulateOutcome(c, minor.outcome);
    SCOPED_TRACE(DescribeParameters(minor, c.parameters));
    const BruteForce b = Sample(*c.profile.initial.H_B, 0, c.spin_axis_B, 20.0);
    EXPECT_EQ(c.spin_axis_B, math::Vec3::UnitX());
    EXPECT_NEAR(o.final_cone_angle, b.cone, kConeTolerance);
    EXPECT_NEAR(o.max_spin_axis_angle, b.max_angle, 2.5e-9);  // [rad] measured 5.3e-10
    EXPECT_EQ(o.final_class, b.cone <= minor.outcome.tumble_angle ? MotionClass::kSpinMinor
                                                                  : MotionClass::kTumbling);
    EXPECT_EQ(AxisName(o.final_axis), "+x");
    EXPECT_EQ(o.flip_count, 0);  // x is never the intermediate axis
    EXPECT_NEAR(o.energy_final, o.energy_initial, 1e-12 * o.energy_initial);
  }
  // Tilted towards the intermediate axis, the cone is the nutation itself.
  const CaseOutcome o5 = SimulateOutcome(BuildCase(minor, 2), minor.outcome);
  EXPECT_NEAR(o5.final_cone_angle, 5.0 * M_PI / 180.0, 1e-12);

  // Spin about the major axis z.
  const SweepSpec major = LoadSweep(
      RigidSweep(*this, "[0, 0, -1]", "  - {parameter: nutation_deg, values: [5, 50]}\n"));
  const CaseOutcome m5 = SimulateOutcome(BuildCase(major, 0), major.outcome);
  const CaseOutcome m50 = SimulateOutcome(BuildCase(major, 1), major.outcome);
  EXPECT_EQ(m5.final_class, MotionClass::kSpinMajor);
  EXPECT_EQ(AxisName(m5.final_axis), "-z");
  EXPECT_EQ(m50.final_class, MotionClass::kTumbling);

  // About the intermediate axis y: an unperturbed spin stays (an unstable equilibrium);
  // a perturbed one tumbles and flips.
  const SweepSpec inter =
      LoadSweep(RigidSweep(*this, "[0, 1, 0]", "  - {parameter: nutation_deg, values: [0, 1]}\n"));
  const CaseOutcome i0 = SimulateOutcome(BuildCase(inter, 0), inter.outcome);
  const CaseOutcome i1 = SimulateOutcome(BuildCase(inter, 1), inter.outcome);
  EXPECT_EQ(i0.final_class, MotionClass::kSpinIntermediate);
  EXPECT_EQ(i0.flip_count, 0);
  EXPECT_EQ(i0.max_spin_axis_angle, 0.0);
  EXPECT_EQ(i1.final_class, MotionClass::kTumbling);
  EXPECT_GE(i1.flip_count, 1);
  EXPECT_GT(i1.max_spin_axis_angle, 3.0);  // a flip turns the axis over (~pi)
}

}  // namespace
}  // namespace deploysim::sweep
