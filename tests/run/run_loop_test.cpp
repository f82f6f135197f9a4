// The one run loop with a body of the test's own (not a profile's): the wing nut's constant
// inertia cut into phases where the test says. The loop's rigid path must give the
// closed-form flips, keep the energy, and its phase boundaries must not touch the
// integration (the same steps, samples and flips as the same body in one phase).

#include "deploysim/run/run_loop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/run/trajectory_schema.h"
#include "test_support.h"

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

/// The wing nut as a body of constant inertia whose phases end at `boundaries`.
class PhasedWingNut final : public RunBody {
 public:
  explicit PhasedWingNut(std::vector<double> boundaries)
      : source_(math::InertiaTensor::FromMatrix(testing::WingNutMoments().asDiagonal())),
        boundaries_(std::move(boundaries)) {}
  const dynamics::InertiaSource& source() const override { return source_; }
  void Start(RunState& st) override {
    st.y.t = 0.0;
    st.y.q_NB = math::Quat::Identity();
    st.y.H_B = testing::WingNutH0();
  }
  RunSample SampleOf(double t,
                     const math::Vec3& H_B,
                     const math::Quat& q_NB,
                     const Eigen::VectorXd& /*x*/,
                     dynamics::Side side) const override {
    const dynamics::InertiaSample js = source_.Evaluate(t, side);
    RunSample o;
    o.t = t;
    o.H_B = H_B;
    o.q_NB = q_NB;
    o.w = dynamics::AngularVelocity(js, H_B);
    o.J_B = js.J_B;
    o.h_rel_B = js.h_rel_B;
    o.kinetic = dynamics::TotalKineticEnergy(js, H_B);
    return o;
  }
  std::vector<double> PhaseBoundaries(double /*t0*/, double /*t1*/) const override {
    return boundaries_;
  }
  PhaseInfo Describe(double t) const override {
    PhaseInfo info;
    std::size_t i = 0;
    while (i < boundaries_.size() && t >= boundaries_[i]) ++i;
    info.name = "phase " + std::to_string(i);
    info.law = "hold";
    info.rigid = true;
    return info;
  }
  analysis::SteadySpin Steady(const RunSample& start, const PhaseInfo& /*info*/) const override {
    return analysis::LinearizeSteadySpin(analysis::FlowOf(start.J_B, start.h_rel_B), start.H_B);
  }

 private:
  dynamics::ConstantInertia source_;
  std::vector<double> boundaries_;
};

/// A compiled run for the loop's settings: the wing nut held 0 to 12 s.
std::shared_ptr<const CompiledRun> WingNutRun(const std::string& method) {
  schedule::Profile p;
  p.name = "wing nut";
  p.model.name = "wing nut";
  p.model.kind = model::ModelKind::kTensors;
  model::Configuration body;
  body.name = "body";
  body.J_B = testing::WingNutMoments().asDiagonal();
  p.model.configurations.push_back(body);
  p.mode = schedule::Mode::kTensor;
  p.initial.q_NB = math::Quat::Identity();
  p.initial.H_B = testing::WingNutH0();
  schedule::Stage st;
  st.name = "hold";
  st.from = st.to = "body";
  st.t_begin = 0.0;
  st.t_end = 12.0;
  p.stages.push_back(st);
  p.output.dt = 0.5;
  p.integrator.method = method;
  p.integrator.rtol = 1e-12;
  p.integrator.atol = 1e-14;
  return CompiledRun::Compile(p);
}

class Collect final : public SampleSink {
 public:
  void Append(const Trajectory& b) override { TrajectorySchema::Standard().Append(all, b); }
  Trajectory all;
};

MissionResult RunPhased(const std::string& method, std::vector<double> boundaries, Trajectory& tr) {
  const auto run = WingNutRun(method);
  PhasedWingNut body(std::move(boundaries));
  Collect sink;
  MissionResult r = RunLoop(*run, body, &sink, {}, RunOptions{});
  tr = std::move(sink.all);
  return r;
}

TEST(RunLoopTest, PhasesOfAnotherBodySplitTheReportNotTheIntegration) {
  for (const std::string method : {"rkf78", "exact"}) {
    Trajectory one, three;
    const MissionResult a = RunPhased(method, {}, one);
    // 5 s is on the output grid, 7.25 s is not.
    const MissionResult b = RunPhased(method, {5.0, 7.25}, three);
    ASSERT_EQ(a.termination, integrators::Termination::kReachedEnd) << a.message;
    ASSERT_EQ(b.termination, integrators::Termination::kReachedEnd) << b.message;
    ASSERT_EQ(a.stages.size(), 1u);
    ASSERT_EQ(b.stages.size(), 3u);
    EXPECT_EQ(b.stages[0].name, "phase 0");
    EXPECT_EQ(b.stages[1].name, "phase 1");
    EXPECT_EQ(b.stages[2].name, "phase 2");
    EXPECT_EQ(b.stages[0].t_end, 5.0);
    EXPECT_EQ(b.stages[1].t_begin, 5.0);
    EXPECT_EQ(b.stages[2].t_begin, 7.25);
    EXPECT_EQ(b.stages[2].t_end, 12.0);
    // The boundaries are only output times: the same steps, samples and flips.
    EXPECT_EQ(a.stats.steps, b.stats.steps) << method;
    EXPECT_EQ(a.flip_times, b.flip_times) << method;
    ASSERT_EQ(one.size(), 25u);
    ASSERT_EQ(three.size(), 25u);
    for (std::size_t i = 0; i < one.size(); ++i) EXPECT_EQ(one.H_B[i], three.H_B[i]) << i;
    // The flips of each phase are its share of the closed form's.
    std::size_t observed = 0;
    for (const StageReport& rep : b.stages) observed += rep.observed_flips.size();
    EXPECT_EQ(observed, b.flip_times.size());
  }
}

TEST(RunLoopTest, FlipsAndEnergyOfTheRigidPathAreTheClosedForms) {
  for (const std::string method : {"rkf78", "exact"}) {
    Trajectory tr;
    const MissionResult r = RunPhased(method, {3.0}, tr);
    // Measured: flips within 1.7e-11 s (rkf78) and 4e-14 s (exact), energy 6e-14, drift 5e-13.
    const std::vector<double> expected = testing::WingNutFlipTimes(12.0);
    ASSERT_EQ(r.flip_times.size(), expected.size()) << method;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      EXPECT_NEAR(r.flip_times[i], expected[i], 5e-11) << method << " flip " << i;
    }
    // A flip turns the spin axis through h_N: the largest angle is nearly pi.
    EXPECT_GT(r.max_spin_axis_angle, 3.1) << method;
    EXPECT_NEAR(r.energy_final, r.energy_initial, 2e-13 * r.energy_initial) << method;
    EXPECT_EQ(r.work.sum(), r.energy_final - r.energy_initial) << method;
    EXPECT_LT(r.max_h_N_drift, 2e-12) << method;
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
