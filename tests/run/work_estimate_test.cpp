// analysis::EstimateWork / CheckWork (runs that hung are refused up front).

#include "deploysim/analysis/work_estimate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/run/mission.h"
#include "run/hinge_fixtures.h"
#include "schedule/schedule_fixtures.h"
#include "test_support.h"

namespace deploysim::run {
namespace {

// The run limits on the estimate of p (what CompiledRun::Compile checks).
void Check(const schedule::Profile& p) { analysis::CheckWork(p, analysis::EstimateWork(p)); }
namespace DEPLOYSIM_TEST_UNIT {

using schedule::Coupling;
using schedule::Law;
using schedule::Mode;
namespace fx = schedule::testing;

schedule::Profile WingNutProfile(double until) {
  schedule::Profile p;
  p.name = "wing_nut";
  p.source = "wn.yaml";
  p.model.name = "wing_nut";
  p.model.kind = model::ModelKind::kTensors;
  p.model.configurations = {
      fx::TensorConfiguration("default", testing::WingNutMoments().asDiagonal())};
  p.initial.H_B = testing::WingNutH0();
  p.stages = {fx::Hold("default", 0.0, until)};
  p.output.dt = until / 100.0;
  return p;
}

// The first stage's bound is the largest |w| on the energy ellipsoid: reached by the
// closed-form motion, never exceeded.
TEST(WorkEstimateTest, FirstStageBoundIsTheLargestRateOfTheMotion) {
  const schedule::Profile p = WingNutProfile(40.0);
  const analysis::WorkEstimate e = analysis::EstimateWork(p);
  ASSERT_EQ(e.stages.size(), 1u);
  const analysis::FreeBodySolution sol(
      math::InertiaTensor::FromPrincipalMoments(testing::WingNutMoments()), testing::WingNutH0());
  double w_max = 0.0;
  for (int i = 0; i <= 400000; ++i) w_max = std::max(w_max, sol.w_NB_B(i * 1e-4).norm());
  EXPECT_LE(w_max, e.stages[0].max_rate * (1.0 + 1e-12));
  EXPECT_GE(w_max, e.stages[0].max_rate * (1.0 - 1e-6));
  EXPECT_NEAR(e.turns, e.stages[0].max_rate * 40.0 / (2.0 * 3.141592653589793), 1e-9);
  EXPECT_NO_THROW(Check(p));
}

// Later stages and moves: M / (a lower bound of I_min) bounds |w| along a real run.
TEST(WorkEstimateTest, BoundsTheRateOfEveryStage) {
  for (const Mode mode : {Mode::kTensor, Mode::kGeometry}) {
    const schedule::Profile p = fx::MakeProfile(
        mode == Mode::kGeometry ? fx::HingedModel() : fx::TensorModel(), mode,
        mode == Mode::kGeometry ? Coupling::kExact : Coupling::kQuasiRigid, Law::kMinimumJerk);
    const analysis::WorkEstimate e = analysis::EstimateWork(p);
    const MissionResult r = RunMission(p);
    ASSERT_EQ(e.stages.size(), p.stages.size());
    for (std::size_t i = 0; i < r.trajectory.size(); ++i) {
      const double t = r.trajectory.time[i];
      std::size_t k = 0;
      while (k + 1 < p.stages.size() && t > p.stages[k].t_end) ++k;
      EXPECT_LE(r.trajectory.w_NB_B[i].norm(), e.stages[k].max_rate * (1.0 + 1e-9))
          << "t = " << t << ", stage " << k;
    }
    EXPECT_NO_THROW(Check(p));
  }
}

// Until 1e15 s (the exact flow took ~1e15 steps) and fixed steps past max_steps: refused
// with one line naming the profile and the limit.
TEST(WorkEstimateTest, RefusesRunsPastTheLimits) {
  try {
    Check(WingNutProfile(1e15));
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("wn.yaml: the run asks for up to 1.4e+15 turns", 0), 0u) << m;
    EXPECT_NE(m.find("at most 1e+06 turns per run"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  schedule::Profile p = WingNutProfile(40.0);
  p.integrator.method = "rk4";
  p.integrator.step = 1e-6;
  EXPECT_EQ(analysis::EstimateWork(p).fixed_steps, 4e7);
  EXPECT_NO_THROW(Check(p));
  p.integrator.step = 1e-7;
  EXPECT_THROW(Check(p), std::invalid_argument);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

// Hinge profiles: a horizon of 1e9 s or a free rotor whose constant motor would
// spin it up for days is refused up front, naming the run; the shipped-like deployment
// passes, and its bound is never exceeded by the run.
TEST(WorkEstimateTest, HingeProfilesAreBoundedUpFront) {
  schedule::HingePlan wing = deploysim::testing::SpringHinge(0.2, -30.0, 1.0);
  wing.drive.latch.enabled = true;
  schedule::Profile p = deploysim::testing::SmallsatHingeProfile(wing, wing, 600.0);
  EXPECT_NO_THROW(Check(p));
  const analysis::WorkEstimate e = analysis::EstimateWork(p);
  ASSERT_EQ(e.stages.size(), 1u);
  const MissionResult r = RunMission(p);
  double max_w = 0.0;
  for (const math::Vec3& w : r.trajectory.w_NB_B) max_w = std::max(max_w, w.norm());
  EXPECT_LE(max_w, e.stages[0].max_rate);

  p.until = 1e9;
  try {
    Check(p);
    ADD_FAILURE() << "a 1e9 s run was accepted";
  } catch (const std::invalid_argument& ex) {
    EXPECT_NE(std::string(ex.what()).find("the run, hub and hinges"), std::string::npos)
        << ex.what();
  }
  schedule::HingePlan rotor = deploysim::testing::SpringHinge(0.0, 0.0);
  rotor.drive.motor.kind = schedule::Motor::Kind::kConstant;
  rotor.drive.motor.torque = 1.0;
  schedule::Profile spun =
      deploysim::testing::SmallsatHingeProfile(rotor, schedule::HingePlan{}, 1e5);
  EXPECT_THROW(Check(spun), std::invalid_argument);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
