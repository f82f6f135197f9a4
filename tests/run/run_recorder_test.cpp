// run::RunRecorder, the bookkeeping every mission run shares: samples, the flip rule,
// the spin-axis extrema, phases and progress.

#include "deploysim/run/run_recorder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "deploysim/math/cubic_hermite.h"

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

const math::Vec3 kAxisZ = math::Vec3::UnitZ();

/// Keeps every block it receives.
class Blocks final : public SampleSink {
 public:
  void Append(const Trajectory& block) override { sizes.push_back(block.size()), last = block; }
  std::vector<std::size_t> sizes;
  Trajectory last;
};

RunSample Sample(double t, const math::Vec3& I, const math::Vec3& H) {
  RunSample s;
  s.t = t;
  s.H_B = H;
  s.J_B = I.asDiagonal();
  s.w = H.cwiseQuotient(I);
  s.kinetic = 0.5 * s.w.dot(H);
  return s;
}

TEST(RunRecorderTest, SamplesGoToTheSinkInBlocksWithEveryFieldFilled) {
  Blocks sink;
  RunRecorder rec(kAxisZ, math::Vec3(0, 0, 2), &sink, {}, 0.0, 1.0);
  const std::size_t n = kSampleBlock + 3;
  for (std::size_t k = 0; k < n; ++k) {
    // h_N drifts by 1e-9 relative per sample; the spin axis z is the intermediate axis
    // of J for the second half.
    const double t = static_cast<double>(k) / n;
    const math::Vec3 I = k < n / 2 ? math::Vec3(1, 2, 3) : math::Vec3(1, 3, 2);
    rec.Sample(Sample(t, I, math::Vec3(0, 0, 2.0 * (1.0 + 1e-9 * static_cast<double>(k)))));
  }
  MissionResult out;
  out.run = CompiledRun::Uncompiled({});  // a result assembled by hand
  rec.Finish(out);
  ASSERT_EQ(sink.sizes, (std::vector<std::size_t>{kSampleBlock, 3}));
  const Trajectory& b = sink.last;
  for (std::size_t size :
       {b.H_B.size(), b.w_NB_B.size(), b.q_NB.size(), b.J_B.size(), b.principal_moments.size(),
        b.h_rel_B.size(), b.h_N.size(), b.energy.size(), b.energy_rigid.size(),
        b.energy_spring.size(), b.euler_313.size(), b.spin_axis_angle.size()}) {
    EXPECT_EQ(size, 3u);
  }
  EXPECT_TRUE(b.hinge_angles.empty());  // no hinge angles given: no hinge columns
  EXPECT_DOUBLE_EQ(b.energy_rigid[0], b.energy[0]);
  EXPECT_NEAR(out.max_h_N_drift, 1e-9 * static_cast<double>(n - 1), 1e-15);
  ASSERT_EQ(out.danger_windows.size(), 1u);
  EXPECT_EQ(out.danger_windows[0].t_begin, static_cast<double>(n / 2) / n);
  EXPECT_EQ(out.danger_windows[0].t_end, static_cast<double>(n - 1) / n);
}

TEST(RunRecorderTest, ProgressComesInStepsOfOnePercentAndEndsAtOne) {
  std::vector<double> reported;
  RunRecorder rec(
      kAxisZ, math::Vec3(0, 0, 1), nullptr, [&](double f) { reported.push_back(f); }, 10.0, 20.0);
  for (int k = 0; k <= 10000; ++k) rec.Progress(10.0 + 1e-3 * k);
  // 0, ~0.01, ~0.02, ... (each the first time at least 1 % past the last), then 1.
  ASSERT_GE(reported.size(), 100u);
  ASSERT_LE(reported.size(), 101u);
  EXPECT_EQ(reported.front(), 0.0);
  for (std::size_t i = 1; i + 1 < reported.size(); ++i) {
    EXPECT_GE(reported[i] - reported[i - 1], 0.01);
    EXPECT_LE(reported[i] - reported[i - 1], 0.0101 + 1e-12);  // one 1e-4 sample past 1 %
  }
  EXPECT_EQ(reported.back(), 1.0);
}

TEST(RunRecorderTest, OnlySignChangesThatTheFlipRuleAcceptsAreFlips) {
  RunRecorder rec(kAxisZ, math::Vec3(0, 0, 1), nullptr, {}, 0.0, 10.0);
  const math::Mat3 intermediate = math::Vec3(1, 3, 2).asDiagonal();  // z intermediate
  const math::Mat3 major = math::Vec3(1, 2, 3).asDiagonal();
  rec.CandidateFlip(3.0, intermediate, math::Vec3(1, 0, 0));    // H . z = 0: a flip
  rec.CandidateFlip(1.0, intermediate, math::Vec3(1, 0, 0));    // an earlier one
  rec.CandidateFlip(2.0, major, math::Vec3(1, 0, 0));           // z is the major axis
  rec.CandidateFlip(4.0, intermediate, math::Vec3(1, 0, 0.5));  // a jump, not a zero
  MissionResult out;
  out.run = CompiledRun::Uncompiled({});  // a result assembled by hand
  rec.Finish(out);
  EXPECT_EQ(out.flip_times, (std::vector<double>{1.0, 3.0}));  // sorted
}

TEST(RunRecorderTest, LargestSpinAxisAngleFromExactPointsAndInsideSteps) {
  RunRecorder rec(kAxisZ, math::Vec3(0, 0, 1), nullptr, {}, 0.0, 1.0);
  rec.SpinAxisCos(1.0);
  // f falls then rises inside the step: the Hermite minimum counts.
  const AxisPoint a{0.0, 0.9, -1.0, -1.0}, b{1.0, 0.9, 1.0, 1.0};
  rec.SpinAxisStep(a, b);
  MissionResult out;
  out.run = CompiledRun::Uncompiled({});  // a result assembled by hand
  rec.Finish(out);
  const double f_min = math::CubicHermiteMinimum(0.0, 0.9, -1.0, 1.0, 0.9, 1.0);
  EXPECT_LT(f_min, 0.9);
  EXPECT_EQ(out.max_spin_axis_angle, std::acos(f_min));
  // With an exact minimum given, that one.
  RunRecorder exact(kAxisZ, math::Vec3(0, 0, 1), nullptr, {}, 0.0, 1.0);
  exact.SpinAxisStep(a, b, [] { return 0.5; });
  // A step whose rate does not change sign from - to +: its end only.
  exact.SpinAxisStep(b, AxisPoint{2.0, 0.95, -1.0, -1.0}, [] { return -1.0; });
  MissionResult out2;
  out2.run = CompiledRun::Uncompiled({});
  exact.Finish(out2);
  EXPECT_EQ(out2.max_spin_axis_angle, std::acos(0.5));
}

TEST(RunRecorderTest, PhasesBecomeStageReportsAndAZeroLengthPhaseIsReplaced) {
  Blocks blocks;
  RunRecorder rec(kAxisZ, math::Vec3(0.1, 0, 1), &blocks, {}, 0.0, 3.0);
  const math::Vec3 I(1, 2, 3), H(0.1, 0, 1);
  rec.OpenPhase({"first", "hold", true, false}, Sample(0.0, I, H));
  rec.ClosePhase(Sample(1.0, I, H));
  rec.OpenPhase({"zero length", "free", false, true}, Sample(1.0, I, H));
  rec.OpenPhase({"second", "free", false, true}, Sample(1.0, I, H));  // replaces it
  rec.ClosePhase(Sample(3.0, I, H));
  rec.CandidateFlip(0.5, math::Vec3(1, 3, 2).asDiagonal(), math::Vec3(1, 0, 0));
  MissionResult out;
  out.run = CompiledRun::Uncompiled({});  // a result assembled by hand
  rec.Finish(out);
  ASSERT_EQ(out.stages.size(), 2u);
  EXPECT_EQ(out.stages[0].name, "first");
  EXPECT_EQ(out.stages[0].t_end, 1.0);
  EXPECT_TRUE(out.stages[0].rigid);
  EXPECT_EQ(out.stages[0].regime, "major-axis");  // rigid: the closed-form analysis
  EXPECT_EQ(out.stages[0].observed_flips, (std::vector<double>{0.5}));
  EXPECT_EQ(out.stages[1].name, "second");
  EXPECT_EQ(out.stages[1].t_begin, 1.0);
  EXPECT_EQ(out.stages[1].t_end, 3.0);
  EXPECT_TRUE(out.stages[1].regime.empty());  // not rigid: no closed form
  EXPECT_EQ(out.stages[1].spin_axis_end, analysis::AxisRole::kMajor);
  EXPECT_GT(out.stages[1].separatrix_distance, 0.0);  // major-axis side
}

TEST(RunRecorderTest, AnOutcomeOnlyRunTakesTheDriftFromTheFinalState) {
  RunRecorder rec(kAxisZ, math::Vec3(0, 0, 2), nullptr, {}, 0.0, 1.0);
  EXPECT_FALSE(rec.sampling());
  rec.OpenPhase({"hold", "hold", true, false}, Sample(0.0, math::Vec3(1, 2, 3), {0, 0, 2}));
  rec.ClosePhase(Sample(1.0, math::Vec3(1, 2, 3), {0, 0, 2}));
  MissionResult out;
  out.run = CompiledRun::Uncompiled({});  // a result assembled by hand
  out.final_state.H_B = math::Vec3(0, 0, 2.000002);
  rec.Finish(out);
  EXPECT_NEAR(out.max_h_N_drift, 1e-6, 1e-15);
  EXPECT_TRUE(out.danger_windows.empty());
  EXPECT_TRUE(out.stages.empty());  // an outcome-only run reports no stages
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
