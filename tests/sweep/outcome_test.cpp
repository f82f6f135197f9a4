// The lean per-case outcome (sweep/outcome.h) against the full mission run and against
// the closed-form torque-free solution.

#include "deploysim/sweep/outcome.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/analysis/motion_outcome.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/math/double_double.h"
#include "deploysim/math/inertia.h"
#include "deploysim/run/mission.h"
#include "deploysim/run/run_recorder.h"
#include "deploysim/schedule/deployment_schedule.h"
#include "deploysim/sweep/sweep_file.h"
#include "sweep_test_support.h"

namespace deploysim::sweep {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using testing::SmallsatProfile;
using testing::SpringProfile;
using testing::SweepDirTest;

constexpr double kFlipTimeTolerance = 1e-9;    // [s] same steps, same event search
constexpr double kSameStateTolerance = 1e-12;  // relative: the same final state
constexpr double kMissionSampling = 0.01;      // [s] output grid of the reference run
// The reference samples the angle every 10 ms; the outcome run finds the extrema between
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
    schedule::Profile p = c.profile();
    p.output.dt = kMissionSampling;
    const run::MissionResult m = run::RunMission(p);
    SCOPED_TRACE("case " + std::to_string(i) + " " + DescribeParameters(spec, c.parameters));
    ASSERT_EQ(o.termination, integrators::Termination::kReachedEnd);
    ASSERT_EQ(static_cast<std::size_t>(o.flip_count), m.flip_times.size());
    if (!m.flip_times.empty()) {
      EXPECT_NEAR(o.first_flip_time, m.flip_times[0], kFlipTimeTolerance);
    }
    EXPECT_EQ(c.spin_axis_B, m.spin_axis_B);
    const run::Trajectory& tr = m.trajectory;
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

// One definition of tumbling: a sweep with the default tumble angle calls a case's final
// motion tumbling exactly when the outcome's spin axis passes 45 deg from h_N (its time to
// tumble is measured; the spins start inside 45 deg). A minor-axis spin tilted towards the
// intermediate axis circulates on a cone as wide as its tilt, and the spin axis's largest
// angle from h_N is that cone. (With the former default of 20 deg, the tilts of 30 and 44
// deg were tumbling by the sweep and not by the outcome.)
TEST_F(SweepDirTest, TheSweepsTumblingIsTheOutcomes) {
  Write("rigid_model.yaml",
        "name: rigid\nkind: tensors\nconfigurations:\n  body: {principal_moments: [1.0, 2.0, "
        "3.0]}\n");
  Write("rigid.yaml",
        "name: rigid\nmodel: rigid_model.yaml\ninitial: {angular_velocity: [1, 0, 0]}\n"
        "stages:\n  - {hold: body, until: 20}\nintegrator: {method: exact}\n");
  const SweepSpec spec =
      LoadSweep(Write("s.yaml",
                      "name: r\nbase: rigid.yaml\ngrid:\n"
                      "  - {parameter: nutation_deg, values: [10, 30, 44, 46, 50]}\n"));
  EXPECT_EQ(spec.outcome.tumble_angle, analysis::kTumbleAngle);
  int tumbling = 0;
  for (std::size_t i = 0; i < spec.case_count(); ++i) {
    const CaseOutcome o = SimulateOutcome(BuildCase(spec, i), spec.outcome);
    SCOPED_TRACE(DescribeParameters(spec, BuildCase(spec, i).parameters));
    const bool tumbles = o.final_class == MotionClass::kTumbling;
    EXPECT_EQ(tumbles, o.time_to_tumble_measured != 0);
    EXPECT_EQ(tumbles, o.max_spin_axis_angle > analysis::kTumbleAngle);
    tumbling += tumbles ? 1 : 0;
  }
  EXPECT_EQ(tumbling, 2);  // 46 and 50 deg
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
    const BruteForce b = Sample(*c.profile().initial.H_B, 0, c.spin_axis_B, 20.0);
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

// ---- Horizon-independent outcomes: the same verdict whatever the run's length ----

// The separatrix distance and the predicted time between flips, against the closed form
// evaluated independently (FreeBodySolution of the initial state: a rigid body keeps D),
// and the predicted time between flips against the spacing of the flips the run located.
TEST_F(SweepDirTest, SeparatrixDistanceAndFlipPeriodOfRigidBodies) {
  // About the intermediate axis y, tilted towards z (azimuth 0) or x (azimuth 90).
  const SweepSpec inter =
      LoadSweep(RigidSweep(*this, "[0, 1, 0]",
                           "  - {parameter: nutation_deg, values: [0, 2, 10, 30]}\n"
                           "  - {parameter: nutation_azimuth_deg, values: [0, 90]}\n"));
  for (std::size_t i = 0; i < inter.case_count(); ++i) {
    const Case c = BuildCase(inter, i);
    const CaseOutcome o = SimulateOutcome(c, inter.outcome);
    SCOPED_TRACE(DescribeParameters(inter, c.parameters));
    const analysis::FreeBodySolution sol(
        math::InertiaTensor::FromPrincipalMoments(math::Vec3(1.0, 2.0, 3.0)),
        *c.profile().initial.H_B);
    const double expected = (sol.D() - 2.0) / (3.0 - 1.0);
    // Measured: 6e-17 (D and the run's final state agree to the integration error).
    EXPECT_NEAR(o.final_separatrix_distance, expected, 1e-15);
    if (c.parameters.values[0] == 0.0) {
      EXPECT_EQ(o.final_separatrix_distance, 0.0);  // a pure spin about the intermediate axis
      EXPECT_FALSE(WillFlip(o));
      continue;
    }
    // Tilted towards the major axis z: D > I2; towards the minor axis x: D < I2.
    EXPECT_EQ(o.final_separatrix_distance > 0.0, c.parameters.values[1] == 0.0);
    EXPECT_TRUE(WillFlip(o));
    EXPECT_NEAR(o.predicted_flip_half_period, sol.flip_half_period(),
                1e-13 * sol.flip_half_period());  // measured 9e-15 relative
    // The flips of a longer run come every predicted_flip_half_period.
    const double half = o.predicted_flip_half_period;
    schedule::Profile p = c.profile();
    p.stages.back().t_end = 4.0 * half;
    p.output.dt = 0.05;
    const run::MissionResult m = run::RunMission(p);
    ASSERT_GE(m.flip_times.size(), 3u);
    for (std::size_t k = 1; k < m.flip_times.size(); ++k) {
      EXPECT_NEAR(m.flip_times[k] - m.flip_times[k - 1], half, 1e-12);  // measured 1.4e-13 s
    }
  }
  // About the minor axis x: stable, never flips.
  const SweepSpec minor =
      LoadSweep(RigidSweep(*this, "[1, 0, 0]", "  - {parameter: nutation_deg, values: [5, 60]}\n"));
  for (std::size_t i = 0; i < minor.case_count(); ++i) {
    const CaseOutcome o = SimulateOutcome(BuildCase(minor, i), minor.outcome);
    EXPECT_LT(o.final_separatrix_distance, 0.0);
    EXPECT_EQ(o.predicted_flip_half_period, std::numeric_limits<double>::infinity());
    EXPECT_FALSE(WillFlip(o));
  }
}

/// A momentum (|H| = 1, h2 = 0) of the body diag(2, 3, 5) whose torque-free motion has
/// 1 - k^2 = mc on the minor-axis side, mc = (I3 - I1)(I2 - D) / ((I2 - I1)(I3 - D)),
/// to the rounding of H to doubles.
math::Vec3 NearSeparatrix(long double mc) {
  const long double I1 = 2, I2 = 3, I3 = 5;
  const long double D = ((I3 - I1) * I2 - mc * (I2 - I1) * I3) / ((I3 - I1) - mc * (I2 - I1));
  const long double h1sq = (1 / D - 1 / I3) / (1 / I1 - 1 / I3);
  return math::Vec3(static_cast<double>(std::sqrt(h1sq)), 0.0,
                    static_cast<double>(std::sqrt(1 - h1sq)));
}

/// (D - I2) / (I3 - I1) of a diagonal body in double-double arithmetic (h are doubles:
/// their squares and quotients carry ~1e-32 relative error, so the cancellation of
/// D - I2 leaves far more than double precision).
double SeparatrixDistanceDD(const math::Vec3& I, const math::Vec3& h) {
  using math::DoubleDouble;
  DoubleDouble M2 = 0.0, two_T = 0.0;
  for (int i = 0; i < 3; ++i) {
    M2 += math::TwoProd(h[i], h[i]);
    two_T += math::TwoProd(h[i], h[i]) / I[i];
  }
  return static_cast<double>((M2 - two_T * I[1]) / two_T / (I[2] - I[0]));
}

// analyze's stage table (the run recorder's report of a rigid phase) and the sweep's
// final prediction classify the same motion with the same numbers, bit for bit, down to
// the separatrix; the separatrix distance keeps its accuracy there (the direct D - I2
// keeps only the digits of D above its rounding: none at 1 - k^2 = 1e-15).
TEST_F(SweepDirTest, AnalyzeAndSweepAgreeBitForBitNearTheSeparatrix) {
  struct Body {
    math::Vec3 I, H;
    double mc;  // 1 - k^2 targeted
  };
  const std::vector<Body> bodies = {
      {{2.0, 3.0, 5.0}, NearSeparatrix(1e-9L), 1e-9},
      {{2.0, 3.0, 5.0}, NearSeparatrix(1e-12L), 1e-12},
      {{2.0, 3.0, 5.0}, NearSeparatrix(1e-15L), 1e-15},
      // Exactly on it: M^2 = 2, 2T = 1/3 + 1/6, D = 4 = I2 (2T I2 - M^2 = 1/3 - 2/6).
      {{3.0, 4.0, 6.0}, {1.0, 0.0, 1.0}, 0.0},
  };
  for (const Body& b : bodies) {
    SCOPED_TRACE(::testing::Message() << "1 - k^2 = " << b.mc);
    const math::Mat3 J = b.I.asDiagonal();
    const math::Vec3 s = analysis::InitialSpinAxis(J, b.H);
    // The analyze side: one rigid phase from (J, H) to (J, H).
    struct Discard final : run::SampleSink {
      void Append(const run::Trajectory&) override {}
    } discard;
    run::RunRecorder rec(s, b.H, &discard, {}, 0.0, 1.0);
    run::RunSample at;
    at.H_B = b.H;
    at.J_B = J;
    at.w = J.inverse() * b.H;
    rec.OpenPhase({"hold", "hold", /*rigid=*/true, false}, at);
    at.t = 1.0;
    rec.ClosePhase(at);
    run::MissionResult m;
    m.run = run::CompiledRun::Uncompiled({});  // a result assembled by hand
    m.final_state.H_B = b.H;
    rec.Finish(m);
    ASSERT_EQ(m.stages.size(), 1u);
    const run::StageReport& stage = m.stages[0];
    // The sweep side.
    const FinalPrediction f = PredictFinal(J, b.H, s);
    EXPECT_EQ(stage.regime, analysis::ToString(f.regime));
    EXPECT_EQ(stage.one_minus_k2, f.one_minus_k2);
    EXPECT_EQ(stage.separatrix_distance, f.separatrix_distance);
    if (b.mc == 0.0) {
      EXPECT_EQ(f.regime, analysis::Regime::kSeparatrix);
      EXPECT_EQ(f.one_minus_k2, 0.0);
      EXPECT_EQ(f.separatrix_distance, 0.0);
      continue;
    }
    EXPECT_EQ(f.regime, analysis::Regime::kMinorAxis);
    EXPECT_NEAR(f.one_minus_k2, b.mc, 0.2 * b.mc);  // H rounded to doubles
    const double reference = SeparatrixDistanceDD(b.I, b.H);
    EXPECT_LT(reference, 0.0);
    // Measured: exact at 1e-9 and 1e-12, 1.6e-16 relative at 1e-15.
    EXPECT_NEAR(f.separatrix_distance, reference, 1e-15 * std::abs(reference));
  }
}

// The same through whole runs: the last stage of analyze's table and the sweep's final
// outcome come from the same end state and the same rule.
TEST_F(SweepDirTest, AnalyzeAndSweepRunsAgreeOnTheFinalSeparatrixDistance) {
  Write("body.yaml",
        "name: b\nkind: tensors\nconfigurations:\n  body: {principal_moments: [2.0, 3.0, 5.0]}\n");
  for (const long double mc : {1e-9L, 1e-12L, 1e-15L}) {
    const math::Vec3 H = NearSeparatrix(mc);
    char text[400];
    std::snprintf(text, sizeof text,
                  "name: near\nmodel: body.yaml\ninitial: {angular_momentum: [%.17g, 0, %.17g]}\n"
                  "stages:\n  - {hold: body, until: 10}\nintegrator: {method: exact}\n",
                  H[0], H[2]);
    const schedule::Profile p = io::LoadProfile(Write("near.yaml", text));
    const run::MissionResult m = run::RunMission(p);
    Case c;
    c.run = run::CompiledRun::Compile(p);
    c.spin_axis_B = m.spin_axis_B;
    const CaseOutcome o = SimulateOutcome(c, OutcomeSettings{});
    ASSERT_EQ(m.stages.size(), 1u);
    EXPECT_EQ(m.stages[0].separatrix_distance, o.final_separatrix_distance);
    EXPECT_EQ(m.max_spin_axis_angle, o.max_spin_axis_angle);
    EXPECT_EQ(m.flip_times.size(), static_cast<std::size_t>(o.flip_count));
    EXPECT_LT(o.final_separatrix_distance, 0.0);
  }
}

// The motivating case: a slow spin of the small satellite does not flip within its 600 s,
// but the motion after the end will; a longer final hold shows the flips where predicted.
TEST_F(SweepDirTest, ASlowSpinThatHasNotFlippedYetWillFlip) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", "name: t\nbase: " + SmallsatProfile() + R"(
integrator: {method: exact, rtol: 1.0e-10, atol: 1.0e-12}
grid:
  - {parameter: spin_rate_rpm, values: [0.3]}
)"));
  const Case c = BuildCase(spec, 0);
  const CaseOutcome o = SimulateOutcome(c, spec.outcome);
  EXPECT_EQ(o.flip_count, 0);
  ASSERT_TRUE(WillFlip(o));
  const double half = o.predicted_flip_half_period;
  EXPECT_GT(half, 600.0);
  // The same case with the final hold longer by three half periods.
  SweepSpec longer = spec;
  longer.base.stages.back().t_end += 3.0 * half;
  const CaseOutcome l = SimulateOutcome(BuildCase(longer, 0), longer.outcome);
  EXPECT_GE(l.flip_count, 2);
  // The same motion after the deployment (to the integration error; measured 4e-16).
  EXPECT_NEAR(l.predicted_flip_half_period, half, 1e-13 * half);
  schedule::Profile p = BuildCase(longer, 0).profile();
  p.output.dt = 1.0;
  const run::MissionResult m = run::RunMission(p);
  ASSERT_GE(m.flip_times.size(), 2u);
  for (std::size_t k = 1; k < m.flip_times.size(); ++k) {
    // Measured: 0 (the closed form after the deployment gives the flips exactly).
    EXPECT_NEAR(m.flip_times[k] - m.flip_times[k - 1], half, 1e-12 * half);
  }
}

// ---- Hinge profiles: the outcome-only run against the sampled mission ----

// The outcome-only hinge run against the sampled mission of the same case: the latch
// columns against the mission's own hinge events, the horizon-independent columns against
// the mission's last phase report (its separatrix distance from the end sample's energy,
// formed directly) and the spacing of the flips after the last latch.
TEST_F(SweepDirTest, HingeOutcomeAgreesWithTheMission) {
  using run::HingeEvent;
  const SweepSpec spec = LoadSweep(Write("s.yaml", "name: t\nbase: " + SpringProfile() + R"(
grid:
  - {parameter: spring_stiffness, values: [0.4, 3]}
  - {parameter: spin_rate_rpm, values: [2, 8]}
)"));
  for (std::size_t i = 0; i < spec.case_count(); ++i) {
    const Case c = BuildCase(spec, i);
    SCOPED_TRACE(DescribeParameters(spec, c.parameters));
    const CaseOutcome o = SimulateOutcome(c, spec.outcome);
    const run::MissionResult m = run::RunMission(c.profile());
    ASSERT_EQ(o.termination, integrators::Termination::kReachedEnd);
    ASSERT_EQ(m.termination, integrators::Termination::kReachedEnd);
    // Hinge events.
    double shock = 0.0, impulse = 0.0, dissipated = 0.0, first_release = 1e300;
    std::int64_t latches = 0;
    for (const HingeEvent& e : m.hinge_events) {
      if (e.kind == HingeEvent::Kind::kRelease) {
        first_release = std::min(first_release, e.t);
        continue;
      }
      latches += e.kind == HingeEvent::Kind::kLatch ? 1 : 0;
      shock = std::max(shock, e.w_jump_B.norm());
      impulse = std::max(impulse, std::abs(e.impulse));
      dissipated += e.energy_dissipated;
    }
    EXPECT_EQ(latches, 2);
    EXPECT_EQ(o.latched_count, 2);
    EXPECT_EQ(o.all_latched, 1);
    // The outcome-only run takes the same steps: equal to rounding (measured: bit-equal).
    EXPECT_NEAR(o.max_latch_w_jump, shock, 1e-12 * shock);
    EXPECT_NEAR(o.max_latch_impulse, impulse, 1e-12 * impulse);
    EXPECT_NEAR(o.energy_dissipated_events, dissipated, 1e-12 * dissipated);
    const double last_latch = std::max(m.latch_times[0], m.latch_times[1]);
    EXPECT_NEAR(o.deploy_end_time, last_latch, 1e-9);
    EXPECT_NEAR(o.deploy_duration, last_latch - first_release, 1e-9);
    EXPECT_NEAR(o.energy_initial, m.energy_initial, 1e-12 * m.energy_initial);
    EXPECT_NEAR(o.energy_final, m.energy_final, 1e-12 * m.energy_final);
    EXPECT_NEAR(o.max_spin_axis_angle, m.max_spin_axis_angle, 1e-9);
    ASSERT_EQ(static_cast<std::size_t>(o.flip_count), m.flip_times.size());
    if (o.flip_count > 0) {
      EXPECT_NEAR(o.first_flip_time, m.flip_times[0], 1e-9);
    }
    // The deployed craft spins about its intermediate axis y: it will flip.
    const run::StageReport& last = m.stages.back();
    EXPECT_EQ(last.spin_axis_end, analysis::AxisRole::kIntermediate);
    EXPECT_NEAR(o.final_separatrix_distance, last.separatrix_distance,
                1e-15);  // measured 1.7e-16
    ASSERT_TRUE(WillFlip(o));
    // The last phase's prediction is made at its start, this one at the end: the same
    // rigid motion to the integration error (measured 1e-11 relative).
    EXPECT_NEAR(o.predicted_flip_half_period, last.predicted_flip_half_period,
                1e-10 * o.predicted_flip_half_period);
    int after = 0;
    for (std::size_t k = 1; k < m.flip_times.size(); ++k) {
      if (m.flip_times[k - 1] < last_latch) continue;
      EXPECT_NEAR(m.flip_times[k] - m.flip_times[k - 1], o.predicted_flip_half_period,
                  1e-10 * o.predicted_flip_half_period);  // measured 4e-12 relative
      ++after;
    }
    if (c.parameters.values[1] > 0.5) {
      EXPECT_GE(after, 1);  // 8 rpm: several flips in 600 s
    }
  }
}

// Failure modes reach the outcome: a failed latch of the first wing leaves the second
// stowed (never released), so does a jam of the first wing part-way; a weak spring
// softens the shock. With one wing stowed, y stays the minor axis: no flip.
TEST_F(SweepDirTest, HingeFailureModesInTheOutcome) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", "name: t\nbase: " + SpringProfile() + R"(
integrator: {rtol: 1.0e-10, atol: 1.0e-12}
grid:
  - {parameter: latch_fails, panel: wing_plus_x, values: [no, yes]}
  - {parameter: stick_fraction, panel: wing_plus_x, values: [0, 0.5]}
  - {parameter: spring_stiffness_scale, values: [1, 0.3]}
)"));
  auto run = [&spec](std::size_t i) { return SimulateOutcome(BuildCase(spec, i), spec.outcome); };
  const CaseOutcome nominal = run(0);  // no, 0, 1
  const CaseOutcome weak = run(1);     // no, 0, 0.3
  const CaseOutcome jam = run(2);      // no, 0.5, 1
  const CaseOutcome failed = run(4);   // yes, 0, 1
  EXPECT_EQ(nominal.latched_count, 2);
  EXPECT_EQ(nominal.all_latched, 1);
  EXPECT_TRUE(WillFlip(nominal));  // deployed: y is the intermediate axis
  EXPECT_LT(weak.max_latch_w_jump, nominal.max_latch_w_jump);
  EXPECT_GT(weak.deploy_duration, nominal.deploy_duration);
  // wing_plus_x jams half-way (45 deg) and wing_minus_x is never released.
  EXPECT_EQ(jam.latched_count, 0);
  EXPECT_EQ(jam.all_latched, 0);
  EXPECT_FALSE(WillFlip(jam));
  EXPECT_EQ(jam.final_class, MotionClass::kSpinMinor);
  EXPECT_EQ(run(6).max_latch_w_jump, jam.max_latch_w_jump);  // a jam before a failed latch
  // wing_plus_x's latch fails: it hits its stop and rests there; wing_minus_x never moves.
  EXPECT_EQ(failed.latched_count, 0);
  EXPECT_EQ(failed.all_latched, 0);
  EXPECT_TRUE(std::isfinite(failed.deploy_end_time));  // the rest on the stop
  EXPECT_GT(failed.max_latch_w_jump, 0.0);
  EXPECT_FALSE(WillFlip(failed));  // one wing stowed: y stays the minor axis
}

// The verdict columns: a minor-axis spinner whose damper's coefficient is swept goes flat
// sooner or later. The time to tumble is measured where the run gets there and predicted
// from the linearization where it does not (not cut off at the horizon), and the outcome
// is the one `analyze` prints for the same case.
TEST_F(SweepDirTest, TimeToTumbleMeasuredOrPredicted) {
  const SweepSpec spec =
      LoadSweep(Write("s.yaml", "name: t\nbase: " + std::string(DEPLOYSIM_SOURCE_DIR) +
                                    "/deployment_profiles/minor_axis_flat_spin.yaml" + R"(
grid:
  - {parameter: damping, values: [0.01, 0.1, 1.0]}
)"));
  std::vector<CaseOutcome> outcomes;
  for (std::size_t i = 0; i < spec.case_count(); ++i) {
    SCOPED_TRACE(i);
    const Case c = BuildCase(spec, i);
    outcomes.push_back(SimulateOutcome(c, spec.outcome));
    const CaseOutcome& o = outcomes.back();
    const analysis::MotionOutcome full = run::RunMission(c.profile()).outcome;
    EXPECT_EQ(o.outcome_class, static_cast<std::int32_t>(full.outcome));
    EXPECT_EQ(o.time_to_tumble_measured, full.time_to_tumble_measured ? 1 : 0);
    EXPECT_NEAR(o.time_to_tumble, full.time_to_tumble, 1e-9 * full.time_to_tumble);
    EXPECT_EQ(o.linear_growth_rate, full.linear.growth_rate);
    // The envelope's rate (from the steps) against the linearization's: 2.2e-4, 9.5e-4
    // and 1.4e-3 apart.
    EXPECT_NEAR(o.nutation_rate, o.linear_growth_rate, 3e-3 * o.linear_growth_rate);
  }
  // The lighter dampers: still growing at 600 s, the tumble predicted 6663 s and 675.0 s
  // after the release; the profile's own damper: 45 deg from h_N 151.8 s after the release,
  // which the linear rate puts 2.9 % earlier (147.4 s: the sink saturates as the
  // nutation grows).
  EXPECT_NEAR(outcomes[0].time_to_tumble, 6663.0, 0.5);
  EXPECT_NEAR(outcomes[1].time_to_tumble, 675.0, 0.05);
  EXPECT_NEAR(outcomes[2].time_to_tumble, 151.82, 0.005);
  EXPECT_EQ(outcomes[2].time_to_tumble_measured, 1);
  EXPECT_NEAR(outcomes[2].transition_time, 270.98, 0.005);  // the separatrix crossing
  // The results file's columns.
  std::map<std::string, ResultColumn> cols;
  for (ResultColumn& c : ResultColumns(spec, outcomes)) cols[c.name] = c;
  EXPECT_EQ(cols.at("outcome").s, (std::vector<std::string>{"growing", "growing", "flat spin"}));
  EXPECT_EQ(cols.at("time_to_tumble_measured").i, (std::vector<std::int64_t>{0, 0, 1}));
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    EXPECT_EQ(cols.at("time_to_tumble").d[i], outcomes[i].time_to_tumble);
    EXPECT_EQ(cols.at("linear_time_constant").d[i], 1.0 / outcomes[i].linear_growth_rate);
    EXPECT_EQ(cols.at("nutation_rate").d[i], outcomes[i].nutation_rate);
  }
  EXPECT_TRUE(std::isnan(cols.at("transition_time").d[0]));
  // docs/sweeps.md explains every outcome column of a hinge sweep.
  std::ifstream in(std::string(DEPLOYSIM_SOURCE_DIR) + "/docs/sweeps.md");
  const std::string docs((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& [name, c] : cols) {
    if (c.role == "outcome") {
      EXPECT_NE(docs.find("`" + name + "`"), std::string::npos) << name;
    }
  }
}

// A slow spin deployed into an intermediate axis: the tilt the deployment leaves lies
// mostly along the saddle's stable direction, so the nutation shrinks within the run
// (1.8 deg to 1.0 deg); the verdict is not "decaying" but bounded within the run, with
// the linear prediction of the tumble.
TEST_F(SweepDirTest, ShrinkingNutationAboutAnUnstableSpinIsNoDecay) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", "name: t\nbase: " + SmallsatProfile() + R"(
grid:
  - {parameter: spin_rate_rpm, values: [0.2]}
)"));
  const Case c = BuildCase(spec, 0);
  const analysis::MotionOutcome o = run::RunMission(c.profile()).outcome;
  ASSERT_TRUE(o.trend.significant());
  EXPECT_LT(o.trend.rate, 0.0);
  EXPECT_EQ(o.linear.verdict, "unstable");
  EXPECT_EQ(o.outcome, analysis::OutcomeClass::kBounded);
  EXPECT_EQ(o.headline.rfind("No growth seen yet about +y (intermediate axis)", 0), 0u)
      << o.headline;
  EXPECT_NE(o.headline.find("45 deg predicted by the linear growth at"), std::string::npos)
      << o.headline;
  EXPECT_NE(o.headline.find("a lower bound"), std::string::npos) << o.headline;
  const CaseOutcome co = SimulateOutcome(c, spec.outcome);
  EXPECT_EQ(OutcomeName(co), "bounded");
  EXPECT_EQ(co.time_to_tumble_measured, 0);
  EXPECT_NEAR(co.time_to_tumble, o.time_to_tumble, 1e-9 * o.time_to_tumble);
}

// The shipped sweep's answer on a few of its cases (the whole sweep is for the README).
TEST(SpringSweepTest, ShockLimitAndTumbleOfTheShippedSweep) {
  const SweepSpec spec =
      LoadSweep(std::string(DEPLOYSIM_SOURCE_DIR) + "/sweeps/smallsat_spring_stiffness_spin.yaml");
  const std::size_t samples = spec.samples();
  const std::size_t spins = spec.grid[1].values.size();
  const double limit = *spec.outcome.latch_shock_limit;
  // Sample 0 (no failure drawn) at the softest spring and slowest spin, and at the
  // stiffest spring and fastest spin.
  const Case soft = BuildCase(spec, 0);
  const Case stiff = BuildCase(spec, spec.case_count() - samples);
  ASSERT_EQ(soft.parameters.sample_index, 0u);
  ASSERT_EQ(stiff.parameters.grid_index, spec.grid_points() - 1);
  ASSERT_EQ(spins, 10u);
  const CaseOutcome a = SimulateOutcome(soft, spec.outcome);
  const CaseOutcome b = SimulateOutcome(stiff, spec.outcome);
  EXPECT_LT(a.max_latch_w_jump, limit);
  EXPECT_GT(b.max_latch_w_jump, limit);
  // Both deploy and will flip: no stiffness or spin rate keeps the deployed craft out of
  // a tumble. The slow one does not flip within the profile's 600 s.
  EXPECT_EQ(a.all_latched, 1);
  EXPECT_EQ(b.all_latched, 1);
  EXPECT_TRUE(WillFlip(a));
  EXPECT_TRUE(WillFlip(b));
  EXPECT_EQ(a.flip_count, 0);
  EXPECT_GT(b.flip_count, 0);
  EXPECT_GT(a.predicted_flip_half_period, 600.0);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::sweep
