// Free-hinge missions: invariants, impulses against their closed forms,
// sequenced releases, stops, jams, and prescribed hinge profiles against stage profiles.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "deploysim/model/mass_matrix.h"
#include "deploysim/run/mission.h"
#include "run/hinge_fixtures.h"

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using testing::kDeg;
using testing::SmallsatHingeProfile;
using testing::SpringHinge;

double TotalEnergy(const Trajectory& tr, std::size_t i) {
  return tr.energy[i] + tr.energy_spring[i];
}

/// (A^-1)_kk of the mass matrix A over (w, theta'_free) at hinge angles theta.
double InverseMassEntry(const model::HingedBody& body,
                        const Eigen::VectorXd& theta,
                        const std::vector<int>& free,
                        int k) {
  const model::HingedBody valid = model::ValidatedHingedBody(body, "test");
  const model::PanelTree tree(valid);
  model::TreePose pose;
  model::ComputePose(valid, tree, theta, pose);
  Eigen::MatrixXd A;
  model::ComputeMassMatrix(valid, tree, pose, free, A);
  const auto it = std::find(free.begin(), free.end(), k);
  const int a = static_cast<int>(it - free.begin());
  return A.inverse()(3 + a, 3 + a);
}

schedule::HingePlan LatchedSpring(double stiffness, double damping) {
  schedule::HingePlan h = SpringHinge(stiffness, -30.0, damping);
  h.drive.latch.enabled = true;
  h.drive.latch.angle = 0.0;
  return h;
}

schedule::HingePlan Locked() { return schedule::HingePlan{}; }

// Acceptance 1: without dampers or motors, E = T + V is constant and h_N exact.
TEST(HingeMissionTest, UndampedSpringsConserveEnergyAndMomentum) {
  schedule::Profile p =
      SmallsatHingeProfile(SpringHinge(0.2, -30.0), SpringHinge(0.15, -20.0), 300.0);
  p.integrator.rtol = 1e-13;
  p.integrator.atol = 1e-15;
  const MissionResult r = RunMission(p);
  ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
  const Trajectory& tr = r.trajectory;
  const double E0 = TotalEnergy(tr, 0);
  double worst = 0.0;
  for (std::size_t i = 0; i < tr.size(); ++i) {
    worst = std::max(worst, std::abs(TotalEnergy(tr, i) - E0) / E0);
  }
  std::printf("undamped: max |E - E0| / E0 = %.3g, h_N drift %.3g, %ld steps\n", worst,
              r.max_h_N_drift, r.stats.steps);
  // Acceptance 1 asks for <= 1e-10; measured 3.2e-12 (h_N 1.9e-15).
  EXPECT_LT(worst, 1e-11);
  EXPECT_LT(r.max_h_N_drift, 1e-14);
  // The wings really swing (not a trivial run).
  double swing = 0.0;
  for (const Eigen::VectorXd& th : tr.hinge_angles)
    swing = std::max(swing, std::abs(th[0] - th[1]));
  EXPECT_GT(swing, 0.1);
}

// Acceptance 1: with dampers the energy decreases monotonically and its loss is the
// integral of sum c theta'^2.
TEST(HingeMissionTest, DampedEnergyDecreasesByTheDampersWork) {
  constexpr double c_plus = 0.3, c_minus = 0.5;
  schedule::Profile p = SmallsatHingeProfile(SpringHinge(0.2, -30.0, c_plus),
                                             SpringHinge(0.15, -20.0, c_minus), 60.0);
  p.integrator.rtol = 1e-12;
  p.output.dt = 0.005;
  const MissionResult r = RunMission(p);
  const Trajectory& tr = r.trajectory;
  for (std::size_t i = 1; i < tr.size(); ++i) {
    ASSERT_LE(TotalEnergy(tr, i), TotalEnergy(tr, i - 1) + 1e-13) << "t = " << tr.time[i];
  }
  // Simpson's rule over the samples (an even number of intervals).
  const std::size_t n = (tr.size() - 1) / 2 * 2;
  auto power = [&](std::size_t i) {
    const Eigen::VectorXd& w = tr.hinge_rates[i];
    return c_plus * w[0] * w[0] + c_minus * w[1] * w[1];
  };
  double dissipated = power(0) + power(n);
  for (std::size_t i = 1; i < n; ++i) dissipated += (i % 2 ? 4.0 : 2.0) * power(i);
  dissipated *= p.output.dt / 3.0;
  const double loss = TotalEnergy(tr, 0) - TotalEnergy(tr, n);
  std::printf("damped: loss %.12g J, integral of c theta'^2 %.12g J, relative %.3g\n", loss,
              dissipated, std::abs(loss - dissipated) / loss);
  EXPECT_GT(loss, 0.1 * TotalEnergy(tr, 0));
  EXPECT_NEAR(loss, dissipated, 2e-12 * loss);  // measured 5.0e-13 (Simpson, rtol 1e-12)
  EXPECT_LT(r.max_h_N_drift, 1e-14);
}

// Acceptance 3: a latch keeps H_B and dissipates theta'^2 / (2 (M^-1)_kk) exactly; the
// energy lost over the run is the sum of the latches' losses.
TEST(HingeMissionTest, LatchDissipatesTheClosedFormAndReleasesTheNextWing) {
  schedule::HingePlan plus = LatchedSpring(0.2, 0.0);
  schedule::HingePlan minus = LatchedSpring(0.2, 0.0);
  minus.drive.release.kind = schedule::Release::Kind::kAfterLatch;
  minus.drive.release.panel = 0;
  minus.drive.release.delay = 2.0;
  const schedule::Profile p = SmallsatHingeProfile(plus, minus, 60.0);
  const MissionResult r = RunMission(p);
  ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
  ASSERT_EQ(r.hinge_events.size(), 4u);  // release, latch, release, latch
  const HingeEvent& latch0 = r.hinge_events[1];
  const HingeEvent& release1 = r.hinge_events[2];
  const HingeEvent& latch1 = r.hinge_events[3];
  EXPECT_EQ(latch0.kind, HingeEvent::Kind::kLatch);
  EXPECT_EQ(latch0.panel, 0);
  EXPECT_EQ(release1.kind, HingeEvent::Kind::kRelease);
  EXPECT_DOUBLE_EQ(release1.t, latch0.t + 2.0);
  EXPECT_EQ(latch1.kind, HingeEvent::Kind::kLatch);
  EXPECT_EQ(latch1.panel, 1);
  EXPECT_EQ(latch0.rate_after, 0.0);
  EXPECT_LT(latch0.rate_before, 0.0);  // 90 deg -> 0: theta decreasing
  // Closed forms: at the first latch only wing 0 is free (wing 1 held at 90 deg); at the
  // second, wing 0 is latched at 0 and only wing 1 is free.
  const double inv0 = InverseMassEntry(p.model.hinged, Eigen::Vector2d(0.0, 90 * kDeg), {0}, 0);
  const double inv1 = InverseMassEntry(p.model.hinged, Eigen::Vector2d(0.0, 0.0), {1}, 1);
  for (const auto& [ev, inv] : {std::pair{latch0, inv0}, std::pair{latch1, inv1}}) {
    const double expected = ev.rate_before * ev.rate_before / (2.0 * inv);
    std::printf("latch at %.6f s: dissipated %.3g relative to the closed form, impulse %.3g\n",
                ev.t, std::abs(ev.energy_dissipated - expected) / expected,
                std::abs(ev.impulse + ev.rate_before / inv) / std::abs(ev.impulse));
    // Measured 1.5e-16 and 1.8e-16 (energy), 0 (impulse): rounding.
    EXPECT_NEAR(ev.energy_dissipated, expected, 2e-15 * expected);
    EXPECT_NEAR(ev.impulse, -ev.rate_before / inv, 2e-15 * std::abs(ev.impulse));
  }
  const Trajectory& tr = r.trajectory;
  const double loss = TotalEnergy(tr, 0) - TotalEnergy(tr, tr.size() - 1);
  std::printf("energy lost over the run against the latches' sum: %.3g relative\n",
              std::abs(loss - latch0.energy_dissipated - latch1.energy_dissipated) / loss);
  EXPECT_NEAR(loss, latch0.energy_dissipated + latch1.energy_dissipated,
              1e-12 * loss);  // measured 3.2e-13 (the integration between the latches)
  EXPECT_LT(r.max_h_N_drift, 1e-14);
  EXPECT_DOUBLE_EQ(r.latch_times[0], latch0.t);
  EXPECT_DOUBLE_EQ(r.latch_times[1], latch1.t);
  // The hub's angular velocity jumps at a latch (the shock), H_B does not.
  EXPECT_GT(latch0.w_jump_B.norm(), 1e-3);
}

// Stops with restitution: each impact reverses the rate times e; the bounces end with
// the panel resting on the stop.
TEST(HingeMissionTest, StopsBounceWithRestitutionAndEndAtRest) {
  schedule::HingePlan plus = SpringHinge(0.2, -30.0);
  plus.drive.stops.min_angle = -2 * kDeg;
  plus.drive.stops.max_angle = 92 * kDeg;
  plus.drive.stops.restitution = 0.5;
  const schedule::Profile p = SmallsatHingeProfile(plus, Locked(), 120.0);
  const MissionResult r = RunMission(p);
  ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
  int stops = 0;
  for (const HingeEvent& e : r.hinge_events) {
    if (e.kind == HingeEvent::Kind::kStop) {
      ++stops;
      EXPECT_NEAR(e.rate_after, -0.5 * e.rate_before, 1e-12 * std::abs(e.rate_before));
      EXPECT_NEAR(e.angle, -2 * kDeg, 0.0);
    }
  }
  EXPECT_GE(stops, 3);
  ASSERT_FALSE(r.hinge_events.empty());
  EXPECT_EQ(r.hinge_events.back().kind, HingeEvent::Kind::kRest);
  const Trajectory& tr = r.trajectory;
  EXPECT_NEAR(tr.hinge_angles.back()[0], -2 * kDeg, 1e-15);
  EXPECT_LT(r.max_h_N_drift, 1e-14);
}

// A jam: the hinge seizes part-way, at jam_fraction of its swing.
TEST(HingeMissionTest, JamLocksThePanelPartWay) {
  schedule::HingePlan plus = LatchedSpring(0.2, 0.1);
  plus.drive.latch.jam_fraction = 0.75;
  const schedule::Profile p = SmallsatHingeProfile(plus, Locked(), 40.0);
  const MissionResult r = RunMission(p);
  ASSERT_GE(r.hinge_events.size(), 2u);
  const HingeEvent& jam = r.hinge_events[1];
  EXPECT_EQ(jam.kind, HingeEvent::Kind::kJam);
  EXPECT_DOUBLE_EQ(jam.angle, 90 * kDeg + 0.75 * (0.0 - 90 * kDeg));
  EXPECT_DOUBLE_EQ(r.trajectory.hinge_angles.back()[0], jam.angle);
}

// Acceptance 4: a hinge profile whose hinges are prescribed along the same laws as a stage
// profile gives the stage profile's result.
TEST(HingeMissionTest, PrescribedHingeProfileReproducesTheStageProfile) {
  schedule::Profile stages;
  stages.name = "stages";
  stages.model = testing::SmallsatModel();
  model::Configuration half;
  half.name = "half";
  half.hinge_angles = Eigen::Vector2d(40 * kDeg, 40 * kDeg);
  stages.model.configurations.push_back(half);
  stages.mode = schedule::Mode::kGeometry;
  stages.coupling = schedule::Coupling::kExact;
  stages.initial.w_NB_B = math::Vec3(0.0091, 0.5235988, 0.0091);
  auto stage = [](const std::string& from, const std::string& to, schedule::Law law, double a,
                  double b) {
    schedule::Stage s;
    s.name = to;
    s.from = from;
    s.to = to;
    s.law = law;
    s.t_begin = a;
    s.t_end = b;
    return s;
  };
  stages.stages = {stage("closed", "closed", schedule::Law::kStep, 0, 10),
                   stage("closed", "half", schedule::Law::kMinimumJerk, 10, 30),
                   stage("half", "half", schedule::Law::kStep, 30, 40),
                   stage("half", "open", schedule::Law::kLinear, 40, 55),
                   stage("open", "open", schedule::Law::kStep, 55, 200)};
  stages.integrator.method = "rkmk-rkf78";
  stages.integrator.rtol = 1e-12;
  stages.integrator.atol = 1e-14;
  stages.output.dt = 0.5;

  schedule::HingePlan h;
  h.kind = schedule::HingePlan::Kind::kPrescribed;
  schedule::HingeMove m1, m2;
  m1.t_begin = 10;
  m1.t_end = 30;
  m1.angle = 40 * kDeg;
  m1.law = schedule::Law::kMinimumJerk;
  m2.t_begin = 40;
  m2.t_end = 55;
  m2.angle = 0.0;
  m2.law = schedule::Law::kLinear;
  h.moves = {m1, m2};
  schedule::Profile hinges = SmallsatHingeProfile(h, h, 200.0);
  hinges.model = stages.model;
  hinges.integrator = stages.integrator;
  hinges.output = stages.output;

  const MissionResult a = RunMission(stages);
  const MissionResult b = RunMission(hinges);
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  // Every sample, those on the linear window's ends (40 s and 55 s, where the hinge rate
  // jumps) included: both hold the state after the jump.
  double dH = 0.0, dq = 0.0, dw = 0.0, dh = 0.0, dT = 0.0, drate = 0.0;
  const Trajectory& ta = a.trajectory;
  const Trajectory& tb = b.trajectory;
  const double H = ta.H_B[0].norm();
  for (std::size_t i = 0; i < ta.size(); ++i) {
    dH = std::max(dH, (ta.H_B[i] - tb.H_B[i]).norm() / H);
    dq = std::max(dq, ta.q_NB[i].angularDistance(tb.q_NB[i]));
    dw = std::max(dw, (ta.w_NB_B[i] - tb.w_NB_B[i]).norm());
    dh = std::max(dh, (ta.h_rel_B[i] - tb.h_rel_B[i]).norm() / H);
    dT = std::max(dT, std::abs(ta.energy[i] - tb.energy[i]) / ta.energy[0]);
    drate = std::max(drate, (ta.hinge_rates[i] - tb.hinge_rates[i]).cwiseAbs().maxCoeff());
  }
  std::printf(
      "prescribed hinge profile vs stage profile: H_B %.3g, attitude %.3g rad, w %.3g rad/s, "
      "h_rel %.3g, energy %.3g, hinge rates %.3g rad/s\n",
      dH, dq, dw, dh, dT, drate);
  // Measured 3.0e-13, 3.3e-13, 9.0e-14, 1.8e-17, 1.2e-15, 0 (a left limit at 40 s and
  // 55 s gave 1.2e-2 rad/s in w).
  EXPECT_LT(dH, 1.5e-12);
  EXPECT_LT(dq, 1.5e-12);
  EXPECT_LT(dw, 5e-13);
  EXPECT_LT(dh, 1e-15);
  EXPECT_LT(dT, 1e-14);
  EXPECT_LT(drate, 1e-15);
  ASSERT_EQ(a.flip_times.size(), b.flip_times.size());
  for (std::size_t i = 0; i < a.flip_times.size(); ++i) {
    EXPECT_NEAR(a.flip_times[i], b.flip_times[i], 1e-9);
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

// Acceptance 4: a free hinge driven by a motor that reproduces a prescribed law gives the
// prescribed result. The motor is a position servo following the law (Motor::kServo,
// critically damped about the wing's inertia on its hinge); as its stiffness grows, the run
// converges to the prescribed run, the difference falling as 1 / stiffness.
TEST(HingeMissionTest, ServoMotorFollowingALawReproducesThePrescribedRun) {
  schedule::HingeMove move;
  move.t_begin = 10.0;
  move.t_end = 30.0;
  move.angle = 0.0;
  move.law = schedule::Law::kMinimumJerk;
  schedule::HingePlan prescribed;
  prescribed.kind = schedule::HingePlan::Kind::kPrescribed;
  prescribed.moves = {move};
  schedule::Profile reference = SmallsatHingeProfile(prescribed, Locked(), 100.0);
  reference.output.dt = 0.5;
  const MissionResult ref = RunMission(reference);
  const double H = ref.trajectory.H_B[0].norm();
  constexpr double kHingeInertia = 1.3;  // [kg m^2] the wing about its hinge, about
  std::vector<double> errors;
  for (double K : {1e2, 1e3, 1e4}) {
    schedule::HingePlan servo;
    servo.kind = schedule::HingePlan::Kind::kFree;
    servo.drive.motor.kind = schedule::Motor::Kind::kServo;
    servo.drive.motor.servo_stiffness = K;
    servo.drive.motor.servo_damping = 2.0 * std::sqrt(K * kHingeInertia);
    servo.drive.motor.follow = {move};
    schedule::Profile p = reference;
    p.hinges = {servo, Locked()};
    const MissionResult r = RunMission(p);
    ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
    double dH = 0.0, dq = 0.0;
    for (std::size_t i = 0; i < r.trajectory.size(); ++i) {
      dH = std::max(dH, (r.trajectory.H_B[i] - ref.trajectory.H_B[i]).norm() / H);
      dq = std::max(dq, r.trajectory.q_NB[i].angularDistance(ref.trajectory.q_NB[i]));
    }
    std::printf("servo stiffness %.0e N m/rad: H_B %.3e, attitude %.3e rad\n", K, dH, dq);
    errors.push_back(std::max(dH, dq));
  }
  // Ten times stiffer, ten times closer (measured: attitude 9.9e-3, 9.9e-4, 9.9e-5 rad;
  // H_B 6.7e-4, 6.7e-5, 6.7e-6; ratios 10.0).
  EXPECT_GT(errors[0] / errors[1], 9.0);
  EXPECT_GT(errors[1] / errors[2], 9.0);
  EXPECT_LT(errors[2], 3e-4);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

// The largest spin-axis angle of an outcome-only run (no samples: located on the steps)
// against the largest over a fine output grid of the full run.
TEST(HingeMissionTest, OutcomeRunLocatesTheLargestSpinAxisAngle) {
  schedule::HingePlan wing = LatchedSpring(0.2, 1.0);
  wing.drive.release.kind = schedule::Release::Kind::kAtTime;
  wing.drive.release.time = 20.0;
  schedule::Profile p = SmallsatHingeProfile(wing, wing, 200.0);
  p.integrator.method = "exact";
  p.integrator.rtol = 1e-10;
  p.integrator.atol = 1e-12;
  p.output.dt = 0.005;
  const MissionResult full = RunMission(p);
  double sampled = 0.0;
  for (double a : full.trajectory.spin_axis_angle) sampled = std::max(sampled, a);
  struct Discard final : SampleSink {
    void Append(const Trajectory&) override {}
  } discard;
  RunOptions o;
  o.sample_trajectory = false;
  const MissionResult lean = RunMission(*CompiledRun::Compile(p), discard, {}, o);
  std::printf("largest spin-axis angle: located %.12f rad, sampled every 5 ms %.12f rad\n",
              lean.max_spin_axis_angle, sampled);
  EXPECT_GE(lean.max_spin_axis_angle, sampled - 1e-9);
  EXPECT_LE(lean.max_spin_axis_angle, sampled + 1e-9);  // measured 3.6e-11 above
  EXPECT_EQ(lean.flip_times.size(), full.flip_times.size());
  EXPECT_EQ(lean.hinge_events.size(), full.hinge_events.size());
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
