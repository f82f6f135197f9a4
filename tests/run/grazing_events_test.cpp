// Events that the motion only just reaches: a hinge that swings a hair past its latch
// (or jam, or stop) angle and back within one integration step, and a spin axis whose
// nutation peaks a hair beyond 45 degrees. Each must be found at every tolerance and by
// every method, at the same time to the tolerance.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "deploysim/integrators/shape_integrate.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/run/mission.h"
#include "deploysim/schedule/free_hinge_system.h"
#include "run/hinge_fixtures.h"

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using testing::kDeg;

/// A 100 kg cube hub with one 10 kg plate hinged on its top edge, stowed at 0 deg.
model::Model PlateModel() {
  model::Model m;
  m.name = "graze";
  m.kind = model::ModelKind::kHinged;
  m.hinged.hub.body.mass = 100.0;
  m.hinged.hub.body.inertia_cm = model::BoxInertia(100.0, math::Vec3(1.0, 1.0, 1.0));
  model::Panel p;
  p.name = "plate";
  p.body.mass = 10.0;
  p.body.inertia_cm = model::BoxInertia(10.0, math::Vec3(1.0, 1.0, 0.02));
  p.hinge_point_B = math::Vec3(0.5, 0.0, 0.5);
  p.hinge_axis_B = math::Vec3::UnitY();
  p.com_offset_B = math::Vec3(0.5, 0.0, 0.01);
  m.hinged.panels.push_back(p);
  model::Configuration c;
  c.name = "stowed";
  c.hinge_angles = Eigen::VectorXd::Zero(1);
  m.configurations = {c};
  return m;
}

const math::Vec3 kSpin(0.01, 0.02, 0.1);  // [rad/s]

/// The plate on a 0.2 N m/rad spring towards 30 deg, released at rest at t = 0: it swings
/// out past 45 deg (the spin's centrifugal load adds to the spring) and back.
schedule::HingePlan Swing() { return testing::SpringHinge(0.2, 30.0); }

schedule::Profile SwingProfile(const schedule::HingePlan& plan,
                               const std::string& method,
                               double rtol) {
  schedule::Profile p;
  p.name = "graze";
  p.source = "graze (test)";
  p.model = PlateModel();
  p.mode = schedule::Mode::kGeometry;
  p.coupling = schedule::Coupling::kExact;
  p.initial.configuration = "stowed";
  p.initial.w_NB_B = kSpin;
  p.hinges = {plan};
  p.start = 0.0;
  p.until = 12.0;
  p.integrator.method = method;
  p.integrator.rtol = method == "rkmk4" ? 1e-6 : rtol;  // rkmk4 uses its step
  p.integrator.atol = 1e-13;
  p.integrator.step = method == "rkmk4" ? rtol : 0.0;  // rkmk4: the fixed step
  p.output.dt = 0.5;
  return p;
}

/// The swing's first peak (time, angle): where the hinge rate falls through 0, located
/// at rtol 1e-13 on the system itself.
std::pair<double, double> SwingPeak() {
  const model::Model m = PlateModel();
  const model::HingedBody body = model::ValidatedHingedBody(m.hinged, "test");
  const std::vector<schedule::HingePlan> plans = {Swing()};
  schedule::FreeHingeSystem sys(body, plans, Eigen::VectorXd::Zero(1));
  integrators::ShapeState y;
  y.H_B = sys.Evaluate(0.0).J_B * kSpin;
  y.x = sys.Free(0, 0.0, y.H_B, Eigen::VectorXd());
  integrators::IntegratorSettings settings;
  settings.tolerances.rtol = 1e-13;
  settings.tolerances.atol = 1e-15;
  // The hinge starts at rest (rate 0, or a rounding error either side of it, which an
  // event on the rate would take for the peak): the search starts a second into the swing.
  const integrators::UniformGridTimes none(0.0, 12.0, 12.0);
  std::size_t next = 0;
  const integrators::ShapeIntegrationResult start =
      integrators::IntegrateShape("rkmk-rkf78", settings, sys, y, 1.0, none, &next, {}, {});
  EXPECT_GT(sys.Snap(1.0, start.final_state.H_B, start.final_state.x).theta_dot[0], 0.0);
  const integrators::ShapeEventFunction peak{
      "peak",
      [&sys](const integrators::ShapeState& s) { return sys.Snap(s.t, s.H_B, s.x).theta_dot[0]; },
      -1, true};
  const integrators::ShapeIntegrationResult r = integrators::IntegrateShape(
      "rkmk-rkf78", settings, sys, start.final_state, 12.0, none, &next, {peak}, {});
  EXPECT_TRUE(r.stopped_at_event);
  return {r.final_state.t, r.final_state.x[0]};
}

struct Case {
  std::string method;
  double tol;  // rtol, or rkmk4's step [s]
};

std::vector<Case> Cases() {
  std::vector<Case> cases;
  for (const char* m : {"rkmk-rkf78", "rkmk-dopri5", "exact"}) {
    for (double tol = 1e-6; tol >= 0.99e-13; tol /= 10.0) cases.push_back({m, tol});
  }
  for (double step : {0.05, 0.02, 0.01, 0.005}) cases.push_back({"rkmk4", step});
  return cases;
}

/// The first event of `kind` on the plate, or a negative time if there is none.
double FirstEvent(const MissionResult& r, HingeEvent::Kind kind) {
  for (const HingeEvent& e : r.hinge_events) {
    if (e.kind == kind) return e.t;
  }
  return -1.0;
}

// A latch, a jam and a stop set a little below the swing's peak: found by every method
// at every tolerance, at the same time to the tolerance.
TEST(GrazingEventTest, LatchJamAndStopBelowThePeakAreAlwaysFound) {
  const auto [t_peak, peak] = SwingPeak();
  ASSERT_GT(peak, 45 * kDeg);
  ASSERT_LT(peak, 50 * kDeg);
  double worst = 0.0;
  for (double depth : {1e-3, 1e-4, 1e-5, 1e-6}) {  // [rad] below the peak
    const double angle = peak - depth;
    schedule::HingePlan latch = Swing();
    latch.drive.latch.enabled = true;
    latch.drive.latch.angle = angle;
    schedule::HingePlan jam = Swing();
    jam.drive.latch.enabled = true;
    jam.drive.latch.angle = 1.0;  // beyond the swing: only the jam is reached
    jam.drive.latch.jam_fraction = angle / 1.0;
    schedule::HingePlan stop = Swing();
    stop.drive.stops.max_angle = angle;
    stop.drive.stops.restitution = 0.5;
    const std::vector<std::pair<schedule::HingePlan, HingeEvent::Kind>> plans = {
        {latch, HingeEvent::Kind::kLatch},
        {jam, HingeEvent::Kind::kJam},
        {stop, HingeEvent::Kind::kStop}};
    for (const auto& [plan, kind] : plans) {
      const double t_ref = FirstEvent(RunMission(SwingProfile(plan, "rkmk-rkf78", 1e-13)), kind);
      ASSERT_GT(t_ref, 0.0);
      ASSERT_LT(t_ref, t_peak);
      for (const Case& c : Cases()) {
        // The hinge angle's error at the peak is about tol (rkmk4: its step^4); the time
        // of a crossing at depth d is that over the rate there, sqrt(2 d theta'').
        const MissionResult r = RunMission(SwingProfile(plan, c.method, c.tol));
        const double t = FirstEvent(r, kind);
        char what_c[160];
        std::snprintf(what_c, sizeof what_c, "%s %g rad below, %s %g", ToString(kind).c_str(),
                      depth, c.method.c_str(), c.tol);
        const std::string what = what_c;
        const double tol = c.method == "rkmk4" ? std::pow(c.tol, 4) : c.tol;
        const double err = std::abs(t - t_ref);
        ASSERT_GT(t, 0.0) << what << ": not found";
        // The crossing's time error: the angle's error (about the tolerance) over the
        // rate there, which goes as sqrt(depth). Measured ratios err sqrt(depth) / tol:
        // rkf78 0.105, dopri5 0.59 (5.4 at 1e-13, where the reference's own error counts:
        // tol floored at 1e-12), rkmk4 7.6e-5.
        const double scale = c.method == "rkmk-dopri5" ? 3.0 : c.method == "rkmk4" ? 3e-4 : 0.3;
        const double ratio = err * std::sqrt(depth) / std::max(tol, 1e-12);
        worst = std::max(worst, ratio / scale);
        EXPECT_LT(ratio, scale) << what;
      }
    }
  }
  std::printf("largest event time error over its bound: %.3g\n", worst);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
