// The trap families of free-hinge inputs that once never finished, broke their stops or
// drifted (docs/design.md 2.7, "Contact, friction and cost"): each finishes with a correct
// event table, checked against a hand calculation where there is one, or is refused in one
// line before it runs. Run time is not asserted here (benchmarks time things); the step
// counts are, deterministically, and the work estimate says each run is short.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/analysis/work_estimate.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/run/mission.h"
#include "deploysim/schedule/free_hinge_system.h"
#include "run/hinge_fixtures.h"

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using testing::kDeg;
using testing::SmallsatHingeProfile;
using Kind = HingeEvent::Kind;

schedule::HingePlan Locked() { return schedule::HingePlan{}; }

schedule::HingePlan Free() {
  schedule::HingePlan h;
  h.kind = schedule::HingePlan::Kind::kFree;
  return h;
}

std::vector<const HingeEvent*> EventsOf(const MissionResult& r, Kind kind) {
  std::vector<const HingeEvent*> out;
  for (const HingeEvent& e : r.hinge_events) {
    if (e.kind == kind) out.push_back(&e);
  }
  return out;
}

/// Every sample's and every event's angle of panel k lies within its stops (to rounding).
void ExpectWithinStops(const MissionResult& r, int k, const schedule::Stops& st) {
  const double tol = 1e-12;
  for (std::size_t i = 0; i < r.trajectory.time.size(); ++i) {
    const double th = r.trajectory.hinge_angles[i][k];
    ASSERT_GE(th, st.min_angle - tol) << "sample at t = " << r.trajectory.time[i];
    ASSERT_LE(th, st.max_angle + tol) << "sample at t = " << r.trajectory.time[i];
  }
  for (const HingeEvent& e : r.hinge_events) {
    if (e.panel != k) continue;
    ASSERT_GE(e.angle, st.min_angle - tol) << ToString(e.kind) << " at " << e.t;
    ASSERT_LE(e.angle, st.max_angle + tol) << ToString(e.kind) << " at " << e.t;
  }
}

/// The largest rise of E = T + V above its start plus the work of the sources (motors,
/// drives) over the samples [J]: dampers, friction and impacts only take energy out.
double EnergyRiseWithoutSource(const MissionResult& r) {
  const Trajectory& tr = r.trajectory;
  const double e0 = tr.energy[0] + tr.energy_spring[0];
  double rise = -1e300;
  for (std::size_t i = 0; i < tr.time.size(); ++i) {
    const double e = tr.energy[i] + tr.energy_spring[i];
    rise = std::max(rise, e - e0 - tr.work_motor[i] - tr.work_drive[i]);
  }
  return rise;
}

/// wing_plus_x free from its stowed angle (90 deg) with a spring towards -30 deg, stops
/// `gap_deg` apart below 90 deg with restitution e; the other wing locked.
schedule::Profile StopsTrap(double e, double gap_deg) {
  schedule::HingePlan h = Free();
  h.drive.spring.stiffness = 0.2;
  h.drive.spring.rest_angle = -30.0 * kDeg;
  h.drive.stops.min_angle = (90.0 - gap_deg) * kDeg;
  h.drive.stops.max_angle = 90.0 * kDeg;
  h.drive.stops.restitution = e;
  schedule::Profile p = SmallsatHingeProfile(h, Locked(), 600.0);
  p.integrator.rtol = 1e-11;
  p.integrator.atol = 1e-13;
  return p;
}

// Restitution 1 (or 0.999999) between stops 2e-6 deg apart: the rebound would be back on
// the other stop within the contact time, so the first impact is a rest (a rattle the
// run once crawled through); 2 deg apart the panel bounces off the spring side's stop for
// the whole run, losing nothing at e = 1.
TEST(TrapFamiliesTest, RestitutionOneBetweenCloseStopsRestsAndBetweenWideStopsBounces) {
  for (const double e : {1.0, 0.999999}) {
    SCOPED_TRACE("restitution " + std::to_string(e));
    const schedule::Profile close = StopsTrap(e, 2e-6);
    const MissionResult rc = RunMission(close);
    ASSERT_EQ(rc.termination, integrators::Termination::kReachedEnd) << rc.message;
    ASSERT_EQ(rc.hinge_events.size(), 2u);  // release, rest
    EXPECT_EQ(rc.hinge_events[1].kind, Kind::kRest);
    EXPECT_EQ(rc.hinge_events[1].angle, close.hinges[0].drive.stops.min_angle);
    EXPECT_EQ(rc.hinge_events[1].rate_after, 0.0);
    ExpectWithinStops(rc, 0, close.hinges[0].drive.stops);
    EXPECT_LT(rc.stats.steps, 1000);  // measured 435

    const schedule::Profile wide = StopsTrap(e, 2.0);
    const MissionResult rw = RunMission(wide);
    ASSERT_EQ(rw.termination, integrators::Termination::kReachedEnd) << rw.message;
    const schedule::Stops& st = wide.hinges[0].drive.stops;
    std::size_t on_min = 0, on_max = 0;
    for (const HingeEvent* s : EventsOf(rw, Kind::kStop)) {
      EXPECT_NEAR(s->rate_after, -e * s->rate_before, 1e-12 * std::abs(s->rate_before));
      EXPECT_TRUE(s->angle == st.min_angle || s->angle == st.max_angle) << s->angle;
      (s->angle == st.min_angle ? on_min : on_max) += 1;
    }
    // The swing from 90 to 88 deg and back takes 0.736 s: 815 impacts in 600 s on the
    // spring's side. At e = 1 the panel comes back to its release angle, the other stop,
    // at rest up to rounding: a touch there at each turning point at most.
    EXPECT_GE(on_min, 800u);
    EXPECT_LE(on_min, 830u);
    EXPECT_LE(on_max, e == 1.0 ? on_min + 1 : 0u);
    EXPECT_TRUE(EventsOf(rw, Kind::kRest).empty());
    ExpectWithinStops(rw, 0, wide.hinges[0].drive.stops);
    EXPECT_LT(analysis::EstimateWork(wide).seconds, 10.0);
  }
}

/// wing_plus_x driven by a constant motor from 90 deg onto its stop at 0 deg.
schedule::Profile MotorPressTrap(double e) {
  schedule::HingePlan h = Free();
  h.drive.motor.kind = schedule::Motor::Kind::kConstant;
  h.drive.motor.torque = -0.5;
  h.drive.stops.min_angle = 0.0;
  h.drive.stops.max_angle = 92.0 * kDeg;
  h.drive.stops.restitution = e;
  return SmallsatHingeProfile(h, Locked(), 600.0);
}

// A motor presses the panel into its stop: the rebounds shrink as e^n and their flights
// with them, so the impact times accumulate at t1 (1 + e) / (1 - e) (t1 the first impact:
// a bouncing ball's geometric series); the panel rests there, once, and stays.
TEST(TrapFamiliesTest, AMotorPressingIntoAStopBouncesToRestAtTheAccumulationTime) {
  for (const double e : {0.5, 0.9}) {
    SCOPED_TRACE("restitution " + std::to_string(e));
    const MissionResult r = RunMission(MotorPressTrap(e));
    ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
    const std::vector<const HingeEvent*> stops = EventsOf(r, Kind::kStop);
    const std::vector<const HingeEvent*> rests = EventsOf(r, Kind::kRest);
    ASSERT_FALSE(stops.empty());
    ASSERT_EQ(rests.size(), 1u);
    EXPECT_EQ(r.hinge_events.back().kind, Kind::kRest);
    for (const HingeEvent* s : stops) {
      EXPECT_NEAR(s->rate_after, -e * s->rate_before, 1e-12 * std::abs(s->rate_before));
    }
    // Measured: 0.03 % (e = 0.5) and 0.6 % (e = 0.9) from the constant-acceleration series
    // (the panel's effective inertia changes with the spin's centrifugal load).
    const double t1 = stops.front()->t;
    EXPECT_NEAR(rests.front()->t, t1 * (1.0 + e) / (1.0 - e), 0.02 * rests.front()->t);
    // The rest: rebound flights below the contact time, or below the angle tolerance.
    EXPECT_LT(stops.size(), e == 0.5 ? 20u : 100u);
    EXPECT_TRUE(EventsOf(r, Kind::kLiftOff).empty());  // the motor keeps pressing
  }
}

/// The hub nearly at rest (H_B ~ 1e-9): what holds a hinge is its drive alone, so the
/// hand calculations below are exact to ~1e-9.
schedule::Profile AtRest(schedule::Profile p) {
  p.initial.w_NB_B = math::Vec3(0.0, 1e-9, 0.0);
  return p;
}

schedule::HingeMove Linear(double to_deg, double t0, double t1) {
  schedule::HingeMove m;
  m.angle = to_deg * kDeg;
  m.t_begin = t0;
  m.t_end = t1;
  m.law = schedule::Law::kLinear;
  return m;
}

/// A servo (0.2 N m/rad) on wing_plus_x, released at 1 s: its plan moves the reference to
/// 0 deg by 0.5 s (so from the release the servo is a spring about 0 deg), then to
/// `to_deg` over [300, 400] s.
schedule::HingePlan ServoHinge(double to_deg) {
  schedule::HingePlan h = Free();
  h.drive.release.kind = schedule::Release::Kind::kAtTime;
  h.drive.release.time = 1.0;
  h.drive.motor.kind = schedule::Motor::Kind::kServo;
  h.drive.motor.servo_stiffness = 0.2;
  h.drive.motor.follow = {Linear(0.0, 0.0, 0.5), Linear(to_deg, 300.0, 400.0)};
  return h;
}

// Exact Coulomb friction: a spring-like servo (K = 0.2 N m/rad about 0) releases the panel
// from 90 deg; each half swing loses 2 mu / K of amplitude (energy: V_n - V_n+1 = mu |dtheta|
// between turning points, where everything is at rest), so the turning points are
// 1.5708, -1.3708, 1.1708, ... rad and the panel sticks at the first with |theta| <= mu / K:
// -0.0292037 rad. It slips again when the servo's plan has pulled its torque past mu:
// K (theta_ref(t) - theta_s) = mu, theta_ref = 0.3 deg/s (t - 300 s): t = 313.521 s.
TEST(TrapFamiliesTest, CoulombFrictionSticksAndSlipsAtTheHandCalculatedTorque) {
  schedule::HingePlan h = ServoHinge(30.0);
  h.drive.friction.torque = 0.02;  // no regularization speed: exact Coulomb
  const schedule::Profile p = AtRest(SmallsatHingeProfile(h, Locked(), 600.0));
  const MissionResult r = RunMission(p);
  ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
  const std::vector<const HingeEvent*> sticks = EventsOf(r, Kind::kStick);
  const std::vector<const HingeEvent*> slips = EventsOf(r, Kind::kSlip);
  ASSERT_EQ(sticks.size(), 2u);
  ASSERT_EQ(slips.size(), 1u);
  const double mu_over_k = 0.02 / 0.2;
  double turning = M_PI / 2.0;
  while (std::abs(turning) > mu_over_k) {
    turning = -turning + (turning > 0.0 ? 2.0 : -2.0) * mu_over_k;
  }
  EXPECT_NEAR(turning, -0.0292037, 1e-7);
  EXPECT_NEAR(sticks[0]->angle, turning, 1e-8);
  const double t_slip = 300.0 + (turning + mu_over_k) / (0.3 * kDeg);
  EXPECT_NEAR(t_slip, 313.521, 1e-3);
  EXPECT_NEAR(slips[0]->t, t_slip, 1e-6);
  EXPECT_GT(sticks[1]->t, slips[0]->t);
  // Friction only takes energy out (the servo is the source).
  EXPECT_LE(EnergyRiseWithoutSource(r), 1e-9);
}

// A panel resting on its stop lifts off when the torque holding it there pulls it away:
// the servo's reference crosses the stop's angle (10 deg) at 320 s.
TEST(TrapFamiliesTest, APanelRestingOnItsStopLiftsOffWhenItsTorquePullsItAway) {
  schedule::HingePlan h = ServoHinge(50.0);
  h.drive.stops.min_angle = 10.0 * kDeg;
  h.drive.stops.max_angle = 92.0 * kDeg;
  h.drive.stops.restitution = 0.5;
  const MissionResult r = RunMission(AtRest(SmallsatHingeProfile(h, Locked(), 600.0)));
  ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
  const std::vector<const HingeEvent*> rests = EventsOf(r, Kind::kRest);
  const std::vector<const HingeEvent*> lifts = EventsOf(r, Kind::kLiftOff);
  ASSERT_EQ(rests.size(), 1u);
  ASSERT_EQ(lifts.size(), 1u);
  EXPECT_EQ(lifts[0]->angle, 10.0 * kDeg);
  EXPECT_NEAR(lifts[0]->t, 320.0, 1e-6);
  EXPECT_EQ(r.hinge_events.back().kind, Kind::kLiftOff);
  ExpectWithinStops(r, 0, h.drive.stops);
}

// A spring rest angle of 1e12 deg stores 1e23 J: refused in one line before the run.
TEST(TrapFamiliesTest, AnAbsurdRestAngleIsRefused) {
  schedule::HingePlan h = Free();
  h.drive.spring.stiffness = 0.2;
  h.drive.spring.rest_angle = 1e12 * kDeg;
  h.drive.damping = 1.0;
  const schedule::Profile p = SmallsatHingeProfile(h, Locked(), 600.0);
  try {
    schedule::ValidateProfile(p);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("spring.rest_angle_deg = 1e+12: must be within +-3600 deg"), std::string::npos)
        << m;
    EXPECT_EQ(m.find('\n'), std::string::npos);
  }
}

/// n small panels (0.1 kg, 0.1 m) on the smallsat's hub, hinged along y, panel k hanging
/// on panel parent_of(k) (-1: the hub); the panels in `free` are free (a weak spring and
/// damper), the others locked.
schedule::Profile PanelTree(int n, int (*parent_of)(int), const std::vector<int>& free) {
  schedule::Profile p = SmallsatHingeProfile(Locked(), Locked(), 600.0);
  model::HingedBody& b = p.model.hinged;
  b.panels.clear();
  for (int k = 0; k < n; ++k) {
    model::Panel pn;
    pn.name = "p" + std::to_string(k);
    pn.body.mass = 0.1;
    pn.body.inertia_cm = model::BoxInertia(0.1, math::Vec3(0.1, 0.2, 0.01));
    pn.hinge_point_B = k == 0 ? math::Vec3(0.3, 0.0, 0.0) : math::Vec3(0.1, 0.0, 0.0);
    pn.hinge_axis_B = math::Vec3::UnitY();
    pn.com_offset_B = math::Vec3(0.05, 0.0, 0.0);
    pn.parent = parent_of(k);
    b.panels.push_back(pn);
  }
  model::Configuration c;
  c.name = "closed";
  c.hinge_angles = Eigen::VectorXd::Constant(n, 10.0 * kDeg);
  p.model.configurations = {c};
  p.hinges.assign(static_cast<std::size_t>(n), Locked());
  for (int k : free) {
    schedule::HingePlan& h = p.hinges[static_cast<std::size_t>(k)];
    h = Free();
    h.drive.spring.stiffness = 0.01;
    h.drive.damping = 0.001;
  }
  p.initial.w_NB_B = math::Vec3(0.01, 0.5, 0.01);
  p.integrator.rtol = 1e-10;
  p.integrator.atol = 1e-12;
  return p;
}

// 64 free panels in a chain: the outer links swing at ~340 rad/s and each step solves a
// 67 x 67 mass matrix, about 5 h on one core: refused in one line with the estimate and
// what to change.
TEST(TrapFamiliesTest, AChainOf64FreePanelsIsRefusedWithItsCost) {
  std::vector<int> all(64);
  for (int k = 0; k < 64; ++k) all[static_cast<std::size_t>(k)] = k;
  const schedule::Profile p = PanelTree(
      64, [](int k) { return k - 1; }, all);
  try {
    schedule::ValidateProfile(p);
    analysis::CheckWork(p,
                        analysis::EstimateWork(p));  // what CompiledRun::Compile asks of every run
    FAIL() << "accepted: " << analysis::DescribeWork(analysis::EstimateWork(p));
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("the run is estimated"), std::string::npos) << m;
    EXPECT_NE(m.find("rule: at most 3.6e+03 s estimated per run"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos);
  }
}

// 2048 panels in a binary tree (panel k on panel (k - 1) / 2), only the last leaf free:
// the locked subtrees are merged into their parents, so each step computes the free
// panel's 11 ancestors and itself (it took 69 s with every panel computed; now 0.7 s, the
// same 4645 steps). The merged body has the full body's inertia.
TEST(TrapFamiliesTest, ATreeOf2048PanelsWithOneFreeComputesOnlyItsBranch) {
  const schedule::Profile p =
      PanelTree(2048, [](int k) { return k == 0 ? -1 : (k - 1) / 2; }, {2047});
  const model::HingedBody body = model::ValidatedHingedBody(p.model.hinged, "tree");
  const Eigen::VectorXd& theta0 = p.model.configurations[0].hinge_angles;
  const schedule::FreeHingeSystem sys(body, p.hinges, theta0);
  EXPECT_EQ(sys.panel_count(), 2048);
  EXPECT_EQ(sys.computed_panel_count(), 12);
  const Eigen::VectorXd rest = Eigen::VectorXd::Zero(2048);
  const math::Mat3 J_full = model::ComputeMassProperties(body, theta0, rest).J_B;
  // Measured 2e-12 relative: the rounding of 2047 merges.
  EXPECT_LT((sys.Evaluate(0.0).J_B - J_full).norm(), 1e-11 * J_full.norm());
  const MissionResult r = RunMission(p);
  ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
  EXPECT_LT(r.stats.steps, 6000);
  EXPECT_EQ(r.hinge_events.size(), 1u);  // its release
  EXPECT_LT(analysis::EstimateWork(p).seconds, 10.0);
  // The estimate's steps within a factor of 3 (measured 0.38 of them taken).
  const double ratio = static_cast<double>(r.stats.steps) / analysis::EstimateWork(p).steps;
  EXPECT_GT(ratio, 1.0 / 3.0);
  EXPECT_LT(ratio, 3.0);
}

void CheckStiffSpring(double rest_deg, double until, double bound);

// An undamped 1e6 N m/rad hinge spring (no stops, no latch) swings 2800 periods in 20 s:
// a Runge-Kutta method's energy error grows with every step (2.7e-7 of E over 600 s at
// rtol 1e-11, about 1e-8 over these 20 s); the free segments' energy projection keeps it
// at the steps' own error. The same spring wound 170 deg (4.4e6 J, rates up to 2900
// rad/s: the run that once gained 21 J over 600 s) keeps it too, over 12 s.
TEST(TrapFamiliesTest, AStiffUndampedSpringKeepsItsEnergyToTheTolerance) {
  // Measured 1.0e-13 and 4.0e-12 of E over the samples (dense output between the steps;
  // at the steps' ends the ledger closes to 1e-16).
  CheckStiffSpring(80.0, 20.0, 5e-13);
  CheckStiffSpring(-80.0, 12.0, 1.5e-11);
}

void CheckStiffSpring(double rest_deg, double until, double bound) {
  SCOPED_TRACE("rest angle " + std::to_string(rest_deg));
  schedule::HingePlan h = Free();
  h.drive.spring.stiffness = 1e6;
  h.drive.spring.rest_angle = rest_deg * kDeg;
  schedule::Profile p = SmallsatHingeProfile(h, Locked(), until);
  p.integrator.rtol = 1e-11;
  p.integrator.atol = 1e-13;
  const MissionResult r = RunMission(p);
  ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
  const Trajectory& tr = r.trajectory;
  const double e0 = tr.energy[0] + tr.energy_spring[0];
  double worst = 0.0;
  for (std::size_t i = 0; i < tr.time.size(); ++i) {
    worst = std::max(worst, std::abs(tr.energy[i] + tr.energy_spring[i] - e0));
  }
  std::printf("stiff spring: energy error %.2e of E over %zu steps\n", worst / e0, r.stats.steps);
  EXPECT_LT(worst, bound * e0);
}

// A stiff spring (3.2e5 N m/rad) on a hub at rest, at rtol 1e-6: the automatic first step,
// set by the body's slow rotation, is far too long for the hinge, and its trial state is
// not finite. It once ended the run ("the mass matrix is not positive definite"); it is a
// rejected step, and the run goes on with shorter ones.
TEST(TrapFamiliesTest, ATrialStepThatLeavesNoFiniteStateIsRejected) {
  schedule::HingePlan h = Free();
  h.drive.spring.stiffness = 3.217e5;
  h.drive.spring.rest_angle = 45.0 * kDeg;
  h.drive.stops.min_angle = -2.0 * kDeg;
  h.drive.stops.max_angle = 92.0 * kDeg;
  h.drive.stops.restitution = 1.0;
  schedule::Profile p = AtRest(SmallsatHingeProfile(Locked(), h, 5.0));
  p.integrator.rtol = 1e-6;
  p.integrator.atol = 1e-13;
  const MissionResult r = RunMission(p);
  ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
  EXPECT_GT(r.stats.rejected, 0);
  ExpectWithinStops(r, 1, h.drive.stops);
}

// At every accepted tolerance no hinge angle leaves its stops (at every sample and every
// event) and the energy rises above its start plus the sources' work by no more than the
// tolerance allows: the event locator finds contacts whatever atol is.
TEST(TrapFamiliesTest, StopsHoldAndEnergyDoesNotRiseAtEveryAcceptedTolerance) {
  const std::vector<std::pair<double, double>> tolerances = {
      {schedule::kMaxRtol, schedule::kMaxAtol}, {1e-6, 1e-8}, {1e-12, 1e-13}};
  std::vector<schedule::Profile> traps = {StopsTrap(1.0, 2.0), MotorPressTrap(0.9)};
  {
    schedule::HingePlan h = Free();
    h.drive.spring.stiffness = 0.2;
    h.drive.spring.rest_angle = -30.0 * kDeg;
    h.drive.damping = 1.0;
    h.drive.stops.min_angle = -2.0 * kDeg;
    h.drive.stops.max_angle = 92.0 * kDeg;
    h.drive.stops.restitution = 0.3;
    traps.push_back(SmallsatHingeProfile(h, Locked(), 120.0));  // no latch: it hits -2 deg
  }
  for (schedule::Profile p : traps) {
    for (const auto& [rtol, atol] : tolerances) {
      SCOPED_TRACE("rtol " + std::to_string(rtol) + " atol " + std::to_string(atol));
      p.integrator.rtol = rtol;
      p.integrator.atol = atol;
      const MissionResult r = RunMission(p);
      ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
      ExpectWithinStops(r, 0, p.hinges[0].drive.stops);
      const double e0 = r.trajectory.energy[0] + r.trajectory.energy_spring[0];
      // The global error of many segments: measured at most 15 tolerances of E0 (e = 1
      // between the wide stops, 1264 impacts, rtol 1e-12), 0.35 at the loosest.
      EXPECT_LE(EnergyRiseWithoutSource(r), 30.0 * std::max(rtol, atol) * e0);
    }
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
