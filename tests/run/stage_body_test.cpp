// The stage profile's body: its phases are the stages, its samples the schedule's, its
// steady spins those of the rigid stages only.

#include "deploysim/run/stage_body.h"

#include <gtest/gtest.h>

#include <vector>

#include "run/stage_fixtures.h"

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

/// Hold 0-2 s stowed, deploy 2-6 s (linear: J_B's rate jumps at both ends), hold 6-10 s.
schedule::Profile ThreeStages() {
  using schedule::Law;
  using testing::MakeStage;
  return testing::TwoShapeProfile(
      "three stages", math::Vec3(0.01, 0.02, 1.0),
      {MakeStage("stowed", "stowed", "stowed", Law::kLinear, 0.0, 2.0),
       MakeStage("deploy", "stowed", "deployed", Law::kLinear, 2.0, 6.0),
       MakeStage("deployed", "deployed", "deployed", Law::kLinear, 6.0, 10.0)});
}

TEST(StageBodyTest, PhasesAreTheStages) {
  const auto run = CompiledRun::Compile(ThreeStages());
  const StageBody body(*run);
  EXPECT_EQ(body.PhaseBoundaries(0.0, 10.0), (std::vector<double>{2.0, 6.0}));
  // A run cut short keeps the boundaries inside it only.
  EXPECT_EQ(body.PhaseBoundaries(0.0, 6.0), (std::vector<double>{2.0}));
  const std::vector<const char*> names = {"stowed", "deploy", "deployed"};
  const std::vector<double> begins = {0.0, 2.0, 6.0};
  for (std::size_t i = 0; i < names.size(); ++i) {
    for (double t : {begins[i], begins[i] + 1.0}) {
      const PhaseInfo info = body.Describe(t);
      EXPECT_EQ(info.name, names[i]) << t;
      EXPECT_EQ(info.rigid, i != 1) << t;
      EXPECT_EQ(info.law, i == 1 ? "linear" : "hold") << t;
      EXPECT_FALSE(info.rotor) << t;
    }
  }
}

TEST(StageBodyTest, SamplesFollowTheScheduleAndItsJumps) {
  const auto run = CompiledRun::Compile(ThreeStages());
  StageBody body(*run);
  RunState st;
  body.Start(st);
  EXPECT_EQ(st.y.t, 0.0);
  // initial.w_NB_B: H_B = J_B w at t0.
  EXPECT_EQ(st.y.H_B, math::Vec3(0.1, 0.24, 8.0));
  const math::Vec3 H = st.y.H_B;
  const math::Quat q = st.y.q_NB;
  const Eigen::VectorXd none;
  // In the deployment J_B moves linearly: halfway, half of each moment's change.
  const RunSample mid = body.SampleOf(4.0, H, q, none, dynamics::Side::kRight);
  EXPECT_NEAR(mid.J_B(0, 0), 20.0, 1e-12);
  EXPECT_NEAR(mid.J_B(2, 2), 24.0, 1e-12);
  EXPECT_NEAR(mid.kinetic, 0.5 * H.dot(mid.J_B.inverse() * H), 1e-12 * mid.kinetic);
  // J_B is continuous at the deployment's end; its rate jumps there (linear law).
  const RunSample left = body.SampleOf(6.0, H, q, none, dynamics::Side::kLeft);
  const RunSample right = body.SampleOf(6.0, H, q, none, dynamics::Side::kRight);
  EXPECT_TRUE(left.J_B.isApprox(right.J_B, 1e-14));
  // Grid samples inside a rigid stage are the schedule's, evaluated once per stage.
  for (double t : {0.5, 1.5, 7.0, 9.5}) {
    const RunSample g = body.GridSample(t, H, q, 10.0);
    const RunSample s = body.SampleOf(t, H, q, none, dynamics::Side::kRight);
    EXPECT_EQ(g.J_B, s.J_B) << t;
    EXPECT_EQ(g.kinetic, s.kinetic) << t;
  }
}

TEST(StageBodyTest, SteadySpinOnlyWhereTheInertiaHolds) {
  const auto run = CompiledRun::Compile(ThreeStages());
  StageBody body(*run);
  RunState st;
  body.Start(st);
  const Eigen::VectorXd none;
  const RunSample start = body.SampleOf(0.0, st.y.H_B, st.y.q_NB, none, dynamics::Side::kRight);
  const analysis::SteadySpin held = body.Steady(start, body.Describe(0.0));
  EXPECT_TRUE(held.found) << held.reason;
  const RunSample moving = body.SampleOf(2.0, st.y.H_B, st.y.q_NB, none, dynamics::Side::kRight);
  const analysis::SteadySpin changing = body.Steady(moving, body.Describe(2.0));
  EXPECT_FALSE(changing.found);
  EXPECT_EQ(changing.reason, "the inertia changes in this stage");
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
