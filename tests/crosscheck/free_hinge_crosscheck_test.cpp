// The reduced free-hinge model against the independent
// Simbody model (simbody_free_hinges.h) at accuracy 1e-14, with Simbody's own error (its
// run at 1e-12 against 1e-14) beside every figure: a symmetric two-wing spring deployment,
// an asymmetric panel with a latch, a two-segment chain and a branched tree with skew hinge
// axes and latches, a motor-driven hinge, and the pendulum damper (the major-axis rule).

#include "deploysim/crosscheck/free_hinge_crosscheck.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "crosscheck/free_hinge_fixtures.h"

namespace deploysim::crosscheck {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using namespace free_hinge_fixtures;  // NOLINT: the shared test builders

// Required: H_B / |H| and attitude [rad] within 1e-9 over >= 300 s, latch
// times within 1e-8 s, impulses and hub angular-velocity jumps within 1e-9 relative. The
// bounds below sit a few times above the largest measured difference over the six cases
// (reduced rkmk-rkf78/exact at rtol 1e-13 against Simbody at 1e-14), so that a regression
// fails long before the required figure: H_B 5.0e-11 and attitude 5.1e-11 rad (the
// symmetric deployment, which flips: Simbody's own error, 1e-12 against 1e-14, is 5.6e-9
// there), latch times 7.9e-14 s, impulses 4.2e-14, w jumps 4.4e-14, flips 7.1e-10 s,
// total energy 8.6e-13 of E(t0) (the undamped chain; 1.1e-13 in the others).
constexpr double kTrajectoryTolerance = 2e-10;
constexpr double kLatchTimeTolerance = 5e-13;
constexpr double kImpulseTolerance = 2e-13;
constexpr double kFlipTolerance = 3e-9;
constexpr double kEnergyTolerance = 3e-12;
/// 1e-6 relative is required; measured below 1e-14.
constexpr double kCrossingTolerance = 1e-12;

schedule::Profile Tight(schedule::Profile p) {
  p.integrator.method = "exact";  // closed form once every hinge is locked
  p.integrator.rtol = 1e-13;
  p.integrator.atol = 1e-15;
  p.output.dt = 1.0;
  return p;
}

FreeHingeCrosscheckResult Check(const schedule::Profile& p, const char* what) {
  FreeHingeCrosscheckOptions o;
  o.accuracy = 1e-14;
  o.own_error_accuracy = 1e-12;  // Simbody's own error: 1e-12 against 1e-14
  FreeHingeCrosscheckResult r = RunFreeHingeCrosscheck(p, o);
  const FreeHingeCrosscheckResult& s = r;
  std::printf(
      "%s, %.0f s: H_B %.2e (Simbody 1e-12 vs 1e-14: %.2e), attitude %.2e rad (%.2e), "
      "latch times %.2e s (%.2e), impulses %.2e (%.2e), w jumps %.2e (%.2e), flips %.2e s "
      "(%.2e, %zu flips), energy %.2e; reduced %.3f s, Simbody %.2f s\n",
      what, p.t_end() - p.t_begin(), r.difference.max_H_B_relative, s.simbody_self.max_H_B_relative,
      r.difference.max_attitude, s.simbody_self.max_attitude, r.events.max_latch_time,
      s.simbody_self_events.max_latch_time, r.events.max_impulse, s.simbody_self_events.max_impulse,
      r.events.max_w_jump, s.simbody_self_events.max_w_jump, r.max_flip_difference,
      s.simbody_self_flip_difference, r.simbody.flip_times.size(), r.max_energy_difference,
      r.reduced.wall_seconds, r.simbody.stats.wall_seconds);
  EXPECT_TRUE(r.events.same_sequence) << what;
  EXPECT_LE(r.difference.max_H_B_relative, kTrajectoryTolerance) << what;
  EXPECT_LE(r.difference.max_attitude, kTrajectoryTolerance) << what;
  EXPECT_LE(r.events.max_latch_time, kLatchTimeTolerance) << what;
  EXPECT_LE(r.events.max_impulse, kImpulseTolerance) << what;
  EXPECT_LE(r.events.max_w_jump, kImpulseTolerance) << what;
  EXPECT_EQ(r.reduced.flip_times.size(), r.simbody.flip_times.size()) << what;
  EXPECT_LE(r.max_flip_difference, kFlipTolerance) << what;
  EXPECT_LE(r.max_energy_difference, kEnergyTolerance) << what;
  return r;
}

TEST(FreeHingeCrosscheckTest, SymmetricTwoWingSpringDeployment) {
  const HingePlan wing = WithLatch(Free(0.3, -30 * kDeg, 0.4), 0.0);
  Check(Tight(HingeProfile(SmallSat(), {wing, wing}, SmallSatSpin(), 300.0)),
        "symmetric spring deployment");
}

TEST(FreeHingeCrosscheckTest, AsymmetricPanelWithALatch) {
  const HingePlan wing = WithLatch(Free(0.3, -30 * kDeg, 0.2), 0.0);
  Check(Tight(HingeProfile(SmallSat(), {wing, Locked()}, SmallSatSpin(), 300.0)),
        "asymmetric panel, latch");
}

TEST(FreeHingeCrosscheckTest, TwoSegmentChainWithLatches) {
  Check(Tight(HingeProfile(
            SkewChain(),
            {WithLatch(Free(0.8, -20 * kDeg, 0.1), 0.0), WithLatch(Free(0.5, 20 * kDeg, 0.1), 0.0)},
            SmallSatSpin(), 300.0)),
        "skew chain, two latches");
}

TEST(FreeHingeCrosscheckTest, BranchedTreeWithSkewAxes) {
  Check(Tight(HingeProfile(
            SkewTree(),
            {WithLatch(Free(0.5, 20 * kDeg, 0.1), 0.0), WithLatch(Free(0.8, -20 * kDeg, 0.1), 0.0),
             WithLatch(Free(0.3, -10 * kDeg, 0.05), 0.0)},
            SmallSatSpin(), 300.0)),
        "branched skew tree");
}

// A prescribed hinge on linear windows that start and end on output times (the hinge
// rate jumps there) beside a free spring hinge: both models write the state after the
// jump, so the angular velocity agrees at those samples as everywhere else.
TEST(FreeHingeCrosscheckTest, LinearWindowsOnOutputTimes) {
  HingePlan moved;
  moved.kind = HingePlan::Kind::kPrescribed;
  schedule::HingeMove open, close;
  open.t_begin = 10.0;
  open.t_end = 30.0;
  open.angle = 40 * kDeg;
  open.law = schedule::Law::kLinear;
  close.t_begin = 40.0;
  close.t_end = 55.0;
  close.angle = 0.0;
  close.law = schedule::Law::kLinear;
  moved.moves = {open, close};
  const HingePlan wing = WithLatch(Free(0.3, -30 * kDeg, 0.4), 0.0);
  const FreeHingeCrosscheckResult r =
      Check(Tight(HingeProfile(SmallSat(), {moved, wing}, SmallSatSpin(), 100.0)),
            "linear windows on output times");
  std::printf("angular velocity: %.3g rad/s (max |w| %.3g)\n", r.difference.max_w,
              r.difference.w_scale);
  EXPECT_LE(r.difference.max_w, 3e-12 * r.difference.w_scale);  // measured 8.8e-13 of max |w|
}

// A wing already swinging at the start (initial.hinge_rates): both models start it with
// that rate and H_B = J w + B theta'.
TEST(FreeHingeCrosscheckTest, PanelReleasedWhileMoving) {
  const HingePlan wing = WithLatch(Free(0.3, -30 * kDeg, 0.2), 0.0);
  schedule::Profile p = HingeProfile(SmallSat(), {wing, Locked()}, SmallSatSpin(), 100.0);
  p.initial.hinge_rates = Eigen::Vector2d(-25 * kDeg, 0.0);
  const FreeHingeCrosscheckResult r = Check(Tight(p), "wing released at -25 deg/s");
  ASSERT_FALSE(r.reduced.trajectory.hinge_rates.empty());
  // The rate and w solved back from (H_B, p): rounding.
  EXPECT_NEAR(r.reduced.trajectory.hinge_rates[0][0], -25 * kDeg, 1e-15);
  EXPECT_LT((r.reduced.trajectory.w_NB_B[0] - SmallSatSpin()).norm(), 1e-15);
}

// A dual-spin craft whose rotor (a free hinge on a bearing, no spring) spins at 10 rad/s
// from the start, with a pendulum nutation damper on the platform.
TEST(FreeHingeCrosscheckTest, RotorSpinningFromTheStart) {
  const model::Model m =
      MakeModel("dual_spin", 60.0, math::Vec3(0.6, 0.6, 1.2),
                {MakePanel("rotor", -1, math::Vec3(0, 0, 0.9), math::Vec3::UnitZ(),
                           math::Vec3::Zero(), 40.0, math::Vec3(0.87, 0.87, 0.6)),
                 MakePanel("damper", -1, math::Vec3(0.3, 0, 0.36), math::Vec3::UnitY(),
                           math::Vec3(0.3, 0, 0), 2.0, math::Vec3(0.08, 0.08, 0.08))},
                Eigen::Vector2d(0.0, 0.0));
  schedule::Profile p =
      HingeProfile(m, {Free(0.0, 0.0, 0.0), Free(0.44, 0.0, 0.5)}, math::Vec3(0.05, 0, 0), 100.0);
  p.initial.hinge_rates = Eigen::Vector2d(10.0, 0.0);
  const FreeHingeCrosscheckResult r = Check(Tight(p), "rotor at 10 rad/s from the start");
  EXPECT_NEAR(r.reduced.trajectory.hinge_rates[0][0], 10.0, 1e-13);
}

TEST(FreeHingeCrosscheckTest, MotorDrivenHinge) {
  HingePlan a = WithLatch(Free(0.0, 0.0, 0.3), 0.0);
  a.drive.motor.kind = schedule::Motor::Kind::kTorqueSpeed;
  a.drive.motor.stall_torque = -0.15;
  a.drive.motor.no_load_speed = -0.2;
  Check(Tight(HingeProfile(SmallSat(), {a, Locked()}, SmallSatSpin(), 300.0)),
        "torque-speed motor");
}

// An undamped two-segment chain on free springs (no latch) is chaotic (docs/design.md 2.7):
// compared over 20 s (over 100 s the two differ by 2.7e-9 in H_B and 4.7e-9 rad, Simbody's
// own error 1.3e-8 and 2.1e-8, and Simbody takes minutes at 1e-14).
TEST(FreeHingeCrosscheckTest, UndampedFreeChainOverAShortHorizon) {
  Check(Tight(HingeProfile(SkewChain(), {Free(0.8, -20 * kDeg), Free(0.5, 20 * kDeg)},
                           SmallSatSpin(), 20.0)),
        "undamped free chain");
}

// The minor-axis spinner with a pendulum damper ends in a flat spin about
// its major axis; the time its spin axis passes 45 degrees agrees with Simbody to 1e-6.
TEST(FreeHingeCrosscheckTest, PendulumDamperMajorAxisRule) {
  schedule::Profile p = Tight(HingeProfile(PendulumDamperSpinner(), {Free(0.2, 0.0, 2.0)},
                                           math::Vec3(0.1, 0.0, 1.0), 300.0));
  const FreeHingeCrosscheckResult r = Check(p, "pendulum damper");
  ASSERT_FALSE(r.reduced.spin_axis_45_crossings.empty());
  std::printf("pendulum damper: 45-degree crossing at %.12f s (reduced) vs %.12f s (Simbody)\n",
              r.reduced.spin_axis_45_crossings.front(), r.simbody_45_crossings.front());
  EXPECT_LE(r.max_45_crossing_difference, kCrossingTolerance);
  // It ends spinning about the major axis of the whole system.
  EXPECT_EQ(analysis::LocateSpinAxis(r.reduced.final_J_B, r.reduced.final_state.H_B).role,
            analysis::AxisRole::kMajor);
}

// Two flexible booms (4 segments each; one bending in two planes through massless links,
// which Simbody takes as massless bodies) on a hub spinning about z with 5 deg of nutation,
// damping ratio 0.02: the chain of spring-damper hinges is the same mechanism in both.
TEST(FreeHingeCrosscheckTest, FlexibleBoomsOnASpinningHub) {
  const model::Model m = BoomSpinner(4, 0.02);
  const double w = 1.0;  // [rad/s]
  Check(Tight(HingeProfile(m, AppendagePlans(m), math::Vec3(w * std::tan(5 * kDeg), 0.0, w), 20.0)),
        "flexible booms");
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::crosscheck
