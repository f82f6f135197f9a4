// The shipped free-hinge examples tell the stories their comments and the README tell, with
// the numbers they quote: the spring-driven deployment of the main job
// (deployment_profiles/smallsat_spring_deploy.yaml), the major-axis rule
// (minor_axis_flat_spin.yaml), dual-spin stability (dual_spin_rotor.yaml against
// dual_spin_locked.yaml) and a jammed wing (smallsat_jammed_wing.yaml). Each run's outcome
// record (motion_outcome.h), the verdict every output prints, is checked against the
// motion it measures. A change to a profile that changes its story fails here, so that its
// comments are updated with it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "deploysim/analysis/flip_rule.h"
#include "deploysim/run/hinge_events.h"
#include "deploysim/run/mission.h"
#include "deploysim/analysis/motion_outcome.h"
#include "deploysim/io/yaml_loader.h"

namespace deploysim {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// The figures the profiles' comments quote are rounded to 3 significant digits; each
// check allows half a unit of the last digit quoted (plus nothing else: the runs are
// deterministic to ~1e-9 s and ~1e-9 relative).
constexpr double kQuotedTime = 0.005;   // [s] times quoted to 0.01 s
constexpr double kQuotedTenth = 0.05;   // [s or deg/s] quoted to 0.1
constexpr double kQuotedAngle = 0.005;  // [deg] angles quoted to 0.01 deg

run::MissionResult RunShipped(const std::string& name) {
  return run::RunMission(io::LoadProfile(std::string(DEPLOYSIM_SOURCE_DIR) +
                                              "/deployment_profiles/" + name + ".yaml"));
}

std::vector<run::HingeEvent> Latches(const run::MissionResult& r) {
  std::vector<run::HingeEvent> out;
  for (const run::HingeEvent& e : r.hinge_events) {
    if (e.kind == run::HingeEvent::Kind::kLatch) out.push_back(e);
  }
  return out;
}

/// The largest angle [deg] between the spin axis and h_N over the samples in [t0, t1].
double MaxSpinAxisAngle(const run::Trajectory& tr, double t0, double t1) {
  double m = 0.0;
  for (std::size_t i = 0; i < tr.size(); ++i) {
    if (tr.time[i] >= t0 && tr.time[i] <= t1) m = std::max(m, tr.spin_axis_angle[i] / kDeg);
  }
  return m;
}

double MinSpinAxisAngle(const run::Trajectory& tr, double t0, double t1) {
  double m = 180.0;
  for (std::size_t i = 0; i < tr.size(); ++i) {
    if (tr.time[i] >= t0 && tr.time[i] <= t1) m = std::min(m, tr.spin_axis_angle[i] / kDeg);
  }
  return m;
}

/// D = |H|^2 / (2 T) at the end of the run, over the largest principal moment of J_B.
double FinalDOverMajor(const run::MissionResult& r) {
  const run::Trajectory& tr = r.trajectory;
  const double h = tr.H_B.back().norm();
  const double d = h * h / (2.0 * tr.energy.back());
  return d / tr.principal_moments.back()(2);
}

// The main job: two wings released 2 s apart, each latched at 15-20 deg/s with a hub
// angular-velocity jump of 2-3 deg/s; then the deployed spin about the intermediate axis
// flips every ~130 s.
TEST(ShippedExamplesTest, SpringDeploymentLatchesGently) {
  const run::MissionResult r = RunShipped("smallsat_spring_deploy");
  const std::vector<run::HingeEvent> latches = Latches(r);
  ASSERT_EQ(latches.size(), 2u);
  const double times[] = {64.17, 71.08};   // s
  const double rates[] = {19.8, 15.0};     // deg/s
  const double jumps[] = {3.2, 1.9};       // deg/s
  const double impulses[] = {0.31, 0.25};  // N m s
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(k);
    EXPECT_EQ(latches[k].panel, k);
    EXPECT_NEAR(latches[k].t, times[k], kQuotedTime);
    EXPECT_NEAR(std::abs(latches[k].rate_before) / kDeg, rates[k], kQuotedTenth);
    EXPECT_NEAR(latches[k].w_jump_B.norm() / kDeg, jumps[k], kQuotedTenth);
    EXPECT_NEAR(latches[k].impulse, impulses[k], kQuotedTime);
  }
  // The second wing is released 2 s after the first latches: swings of 4.2 and 4.9 s.
  EXPECT_NEAR(latches[0].t - 60.0, 4.2, kQuotedTenth);
  EXPECT_NEAR(latches[1].t - (latches[0].t + 2.0), 4.9, kQuotedTenth);
  // Deployed, y is the intermediate axis: 4 flips in 600 s, every 129.6 s; the verdict says so.
  EXPECT_EQ(r.flip_times.size(), 4u);
  const analysis::MotionOutcome& o = r.outcome;
  EXPECT_EQ(o.outcome, analysis::OutcomeClass::kFlipping);
  EXPECT_EQ(o.flips, 4);
  EXPECT_NEAR(o.flip_interval, 129.6, kQuotedTenth);
  EXPECT_EQ(o.role_phase, analysis::AxisRole::kIntermediate);
  EXPECT_EQ(o.linear.verdict, "unstable");
  // 45 deg from h_N predicted from the linear growth at 118 s, first reached at 126 s.
  EXPECT_NEAR(o.predicted_45_time, 118.1, kQuotedTenth);
  EXPECT_TRUE(o.time_to_tumble_measured);
  EXPECT_NEAR(o.phase_begin + o.time_to_tumble, 126.5, kQuotedTenth);
  EXPECT_EQ(o.headline.rfind("Flips every 129.6 s about +y (intermediate axis)", 0), 0u)
      << o.headline;
}

// The major-axis rule: rigid (damper caged) for 60 s, the nutation stays at 0.70-0.71 deg;
// uncaged, the damper drives the minor-axis spin into a flat spin about the major axis.
TEST(ShippedExamplesTest, MinorAxisSpinnerGoesFlat) {
  const run::MissionResult r = RunShipped("minor_axis_flat_spin");
  ASSERT_EQ(r.stages.size(), 2u);
  // The verdicts say what holds only for a rigid body.
  EXPECT_TRUE(r.stages[0].rigid_body_only);
  EXPECT_NE(r.stages[0].caveat.find("stable only for a perfectly rigid body"), std::string::npos)
      << r.stages[0].caveat;
  EXPECT_TRUE(r.stages[1].rigid_body_only);
  EXPECT_NE(r.stages[1].caveat.find("with energy dissipation"), std::string::npos)
      << r.stages[1].caveat;
  const run::Trajectory& tr = r.trajectory;
  EXPECT_NEAR(MinSpinAxisAngle(tr, 0.0, 60.0), 0.70, kQuotedAngle);
  EXPECT_NEAR(MaxSpinAxisAngle(tr, 0.0, 60.0), 0.71, kQuotedAngle);
  ASSERT_EQ(r.spin_axis_45_crossings.size(), 1u);
  EXPECT_NEAR(r.spin_axis_45_crossings[0], 211.8, kQuotedTenth);
  // A flat spin: 84-97 deg from h_N from 300 s on, 86-94 deg over the last 60 s.
  EXPECT_GE(MinSpinAxisAngle(tr, 300.0, 600.0), 84.0);
  EXPECT_LE(MaxSpinAxisAngle(tr, 300.0, 600.0), 97.0);
  EXPECT_GE(MinSpinAxisAngle(tr, 540.0, 600.0), 86.0);
  EXPECT_LE(MaxSpinAxisAngle(tr, 540.0, 600.0), 94.0);
  // D = 8.85 kg m^2: 99.3 % of the largest principal moment; T from 10.1 J to 2.6 J.
  EXPECT_NEAR(FinalDOverMajor(r), 0.993, 0.0005);
  EXPECT_NEAR(r.energy_initial, 10.1, kQuotedTenth);
  EXPECT_NEAR(r.energy_final, 2.6, kQuotedTenth);
  // The verdict is the motion's: a flat spin (minor -> major), the separatrix crossed at
  // 271.0 s; the spin axis 45 deg from h_N at 211.8 s, which the linearization of the
  // uncaged craft (time constant 35.43 s, the envelope's fit 35.45 s) predicts at 207.4 s
  // from the 0.70-degree nutation.
  const analysis::MotionOutcome& o = r.outcome;
  EXPECT_EQ(o.outcome, analysis::OutcomeClass::kTransition);
  EXPECT_EQ(o.outcome_name, "flat spin");
  EXPECT_EQ(o.role_start, analysis::AxisRole::kMinor);
  EXPECT_EQ(o.role_end, analysis::AxisRole::kMajor);
  EXPECT_NEAR(o.transition_time, 271.0, kQuotedTenth);
  EXPECT_EQ(o.transition_time, o.separatrix_time);
  EXPECT_NEAR(o.first_45_time, 211.8, kQuotedTenth);
  EXPECT_NEAR(o.predicted_45_time, 207.4, kQuotedTenth);
  EXPECT_EQ(o.linear.verdict, "unstable");
  EXPECT_NEAR(1.0 / o.linear.growth_rate, 35.43, kQuotedTime);
  ASSERT_TRUE(o.trend.valid);
  EXPECT_NEAR(o.trend.time_constant(), 35.45, kQuotedTime);
  EXPECT_EQ(
      o.headline.rfind("Flat spin: the spin moves from +z (minor axis) to -y (major axis)", 0), 0u)
      << o.headline;
}

// Dual spin: with the rotor held at 10 rad/s and the damper on the despun platform, the
// nutation decays; with the rotor locked, the same craft and damper go flat.
TEST(ShippedExamplesTest, DualSpinRotorStabilizesAndLockedRotorGoesFlat) {
  const run::MissionResult spinning = RunShipped("dual_spin_rotor");
  const run::Trajectory& s = spinning.trajectory;
  EXPECT_TRUE(spinning.spin_axis_45_crossings.empty());
  // Nutation envelope (the largest angle over the 100 s from each time on): 1.85 deg at
  // the start, 0.75 at 100 s, 0.12 at 300 s, 0.008 at 600 s; 0.0005 deg at 900 s.
  EXPECT_NEAR(MaxSpinAxisAngle(s, 0.0, 100.0), 1.85, kQuotedAngle);
  EXPECT_NEAR(MaxSpinAxisAngle(s, 100.0, 200.0), 0.75, kQuotedAngle);
  EXPECT_NEAR(MaxSpinAxisAngle(s, 300.0, 400.0), 0.12, kQuotedAngle);
  EXPECT_NEAR(MaxSpinAxisAngle(s, 600.0, 700.0), 0.008, 0.0005);
  EXPECT_NEAR(s.spin_axis_angle.back() / kDeg, 0.0005, 0.00005);
  // The verdict: stable, decaying with the envelope's time constant 109.95 s (the
  // linearization: 110.0 s, the quasi-rigid estimate 110.7 s), where the rigid-body rule
  // says unstable because of the rotor.
  const analysis::MotionOutcome& so = spinning.outcome;
  EXPECT_EQ(so.outcome, analysis::OutcomeClass::kDecaying);
  ASSERT_TRUE(so.trend.valid);
  EXPECT_NEAR(so.trend.time_constant(), 109.95, kQuotedTenth);
  EXPECT_EQ(so.linear.verdict, "asymptotically stable");
  EXPECT_NEAR(-1.0 / so.linear.growth_rate, 110.0, kQuotedTenth);
  EXPECT_EQ(so.rigid_rule, "unstable");
  EXPECT_NE(so.disagreement.find("rotor"), std::string::npos) << so.disagreement;
  EXPECT_NEAR(-1.0 / so.linear.quasi_rigid_rate, 110.7, kQuotedTenth);
  EXPECT_EQ(so.headline.rfind("Stable: the nutation about +z (minor axis) decays from 1.84 deg "
                              "to 0.000516 deg, time constant 109.9 s",
                              0),
            0u)
      << so.headline;

  const run::MissionResult locked = RunShipped("dual_spin_locked");
  // The same momentum at the start.
  EXPECT_LT((locked.trajectory.H_B.front() - s.H_B.front()).norm(), 2e-4 * s.H_B.front().norm());
  ASSERT_EQ(locked.spin_axis_45_crossings.size(), 1u);
  EXPECT_NEAR(locked.spin_axis_45_crossings[0], 448.4, kQuotedTenth);
  EXPECT_GE(MinSpinAxisAngle(locked.trajectory, 600.0, 900.0), 83.0);
  EXPECT_LE(MaxSpinAxisAngle(locked.trajectory, 600.0, 900.0), 95.0);
  // It ends spinning about the major axis of the whole craft (y).
  EXPECT_EQ(analysis::LocateSpinAxis(locked.final_J_B, locked.final_state.H_B).role,
            analysis::AxisRole::kMajor);
  EXPECT_NEAR(locked.energy_initial, 134.3, kQuotedTenth);
  EXPECT_NEAR(locked.energy_final, 38.3, kQuotedTenth);
  // The verdict: unstable, a flat spin across the separatrix at 654.7 s; 45 deg from h_N at
  // 448.4 s, which the linearization (time constant 141.0 s) predicts at 450.7 s.
  const analysis::MotionOutcome& lo = locked.outcome;
  EXPECT_EQ(lo.outcome_name, "flat spin");
  EXPECT_NEAR(lo.transition_time, 654.7, kQuotedTenth);
  EXPECT_EQ(lo.transition_time, lo.separatrix_time);
  EXPECT_NEAR(lo.first_45_time, 448.4, kQuotedTenth);
  EXPECT_EQ(lo.linear.verdict, "unstable");
  EXPECT_NEAR(1.0 / lo.linear.growth_rate, 141.0, kQuotedTenth);
  EXPECT_NEAR(lo.predicted_45_time, 450.7, kQuotedTenth);
}

// A wing that jams: the verdict names the jam first, with its time and angle, then the
// motion (the craft, one wing out, flips about its intermediate axis).
TEST(ShippedExamplesTest, JammedWingIsTheVerdictsFirstWord) {
  const run::MissionResult r = RunShipped("smallsat_jammed_wing");
  const analysis::MotionOutcome& o = r.outcome;
  ASSERT_EQ(o.faults.size(), 1u);
  EXPECT_EQ(o.faults[0].kind, analysis::DeploymentFault::Kind::kJam);
  EXPECT_EQ(o.faults[0].panel_name, "wing_minus_x");
  EXPECT_NEAR(o.faults[0].t, 69.22, kQuotedTime);
  EXPECT_NEAR(o.faults[0].angle / kDeg, 36.0, kQuotedAngle);
  EXPECT_EQ(o.outcome, analysis::OutcomeClass::kFlipping);
  EXPECT_EQ(o.headline.rfind("Panel wing_minus_x JAMMED at 69.22 s at 36 deg (latch at 0 deg); "
                             "flips every 186 s",
                             0),
            0u)
      << o.headline;
}

// A sweep case runs without samples: its verdict, from the nutation inside the accepted
// steps, is the one `analyze` prints from the samples, for every shipped profile.
TEST(ShippedExamplesTest, OutcomeOnlyRunsGiveTheSameVerdict) {
  for (const char* name : {"asymmetric_sat_deploy", "dual_spin_locked", "dual_spin_rotor",
                           "minor_axis_flat_spin", "seed_limit_j2_to_j1", "seed_limit_j2_to_j3",
                           "seed_satellite", "smallsat_jammed_wing", "smallsat_spring_deploy",
                           "smallsat_three_stage", "smallsat_two_segment_deploy", "wing_nut"}) {
    SCOPED_TRACE(name);
    const schedule::Profile profile = io::LoadProfile(std::string(DEPLOYSIM_SOURCE_DIR) +
                                                      "/deployment_profiles/" + name + ".yaml");
    const run::MissionResult full = run::RunMission(profile);
    run::RunOptions options;
    options.sample_trajectory = false;
    run::NullSink none;
    const run::MissionResult only = run::RunMission(profile, none, {}, options);
    const analysis::MotionOutcome& a = full.outcome;
    const analysis::MotionOutcome& b = only.outcome;
    EXPECT_EQ(b.outcome_name, a.outcome_name);
    EXPECT_EQ(b.flips, a.flips);
    EXPECT_EQ(b.faults.size(), a.faults.size());
    EXPECT_EQ(b.phase_begin, a.phase_begin);
    EXPECT_EQ(b.linear.growth_rate, a.linear.growth_rate);
    EXPECT_EQ(b.time_to_tumble_measured, a.time_to_tumble_measured);
    if (std::isfinite(a.time_to_tumble)) {
      EXPECT_NEAR(b.time_to_tumble, a.time_to_tumble, 1e-9 * a.time_to_tumble);
    } else {
      EXPECT_EQ(std::isinf(b.time_to_tumble), std::isinf(a.time_to_tumble));
      EXPECT_EQ(std::isnan(b.time_to_tumble), std::isnan(a.time_to_tumble));
    }
    // The envelope's rate from the steps' interpolants and from the samples: 2.6e-4
    // (dual_spin_rotor) and 3.4e-3 (minor_axis_flat_spin, a short fit of 9 peaks) apart;
    // from the linearization's, 1.5e-3 and 1.4e-3 (steps), 1.3e-3 and 4.8e-3 (samples).
    // (Fits up to 45 deg give a trend's sign only, and these runs' classes come from
    // their flips and transitions.)
    auto small = [](const analysis::ExponentialFit& f) {
      return f.valid && f.ceiling == analysis::kFitCeiling;
    };
    EXPECT_EQ(small(b.trend), small(a.trend));
    if (small(a.trend) && small(b.trend)) {
      EXPECT_NEAR(b.trend.rate, a.trend.rate, 1e-2 * std::abs(a.trend.rate));
    }
    // The largest nutation: the samples' largest misses a peak between samples by up to
    // 0.017 rad at these output steps; the steps' is the interpolant's peak.
    EXPECT_NEAR(b.nutation_max, a.nutation_max, 0.025);
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim
