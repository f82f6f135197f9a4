// The mission pipeline on the shipped models: the seed thesis's satellite reproduces
// section 3.4 quantitatively, and exact against quasi-rigid coupling shows the physics of
// docs/design.md 2.5.

#include "deploysim/run/mission.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "deploysim/run/coupling_comparison.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/number_format.h"

namespace deploysim {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;

// Writes a profile into a scratch file and loads it through the real reader.
schedule::Profile ProfileFromText(const std::string& name, const std::string& body) {
  const fs::path dir =
      fs::temp_directory_path() / ("deploysim_mission_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path p = dir / (name + ".yaml");
  std::ofstream(p) << "name: " << name << "\n" << body;
  schedule::Profile profile = io::LoadProfile(p.string());
  fs::remove_all(dir);
  return profile;
}

std::string Models() { return std::string(DEPLOYSIM_SOURCE_DIR) + "/models/"; }

// The seed's satellite, one configuration at a time from the seed's initial momentum
// (as in the thesis, Figs. 3.5, 3.7, 3.9).
schedule::Profile SeedConfiguration(const std::string& config) {
  return ProfileFromText("seed_" + config,
                         "model: " + Models() +
                             "seed_satellite.yaml\n"
                             "mode: tensor\ncoupling: quasi-rigid\n"
                             "initial: {angular_momentum: [1.0e-8, 2.1252e-5, 1.0e-8]}\n"
                             "stages:\n  - {hold: " +
                             config +
                             ", until: 40}\n"
                             "integrator: {method: rkmk-rkf78, rtol: 1.0e-12, atol: 1.0e-14}\n"
                             "output: {dt: 0.01}\n");
}

TEST(SeedSatelliteTest, ClosedSpinsStablyWithinThePerturbationBound) {
  const run::MissionResult r = run::RunMission(SeedConfiguration("closed"));
  EXPECT_TRUE(r.flip_times.empty());
  // y is the minor axis: Q = M^2/I_y - 2T = sum_{i != y} H_i^2 (1/I_y - 1/I_i) is
  // conserved, so the transverse momentum obeys |H_perp|^2 <= Q / (1/I_y - 1/I_mid):
  // the spin axis stays within asin(|H_perp|max / M) of h_N.
  const math::Vec3 I = r.trajectory.J_B.front().diagonal();  // (3.036, 0.699, 2.741)e-6
  const math::Vec3 H0 = r.trajectory.H_B.front();
  const double M = H0.norm();
  const double Q =
      H0.x() * H0.x() * (1 / I.y() - 1 / I.x()) + H0.z() * H0.z() * (1 / I.y() - 1 / I.z());
  const double bound = std::asin(std::sqrt(Q / (1 / I.y() - 1 / I.z())) / M);
  double worst = 0.0;
  for (double a : r.trajectory.spin_axis_angle) worst = std::max(worst, a);
  EXPECT_LE(worst, bound * (1 + 1e-9));
  EXPECT_GE(worst, 0.5 * bound);  // the wobble really explores the bound
  ::testing::Test::RecordProperty("closed_max_angle_rad", math::FormatNumber(worst));
  ::testing::Test::RecordProperty("closed_bound_rad", math::FormatNumber(bound));
}

TEST(SeedSatelliteTest, HalfOpenIsTheAxisymmetricSolution) {
  const run::MissionResult r = run::RunMission(SeedConfiguration("half_open"));
  EXPECT_TRUE(r.flip_times.empty());
  // J_y = J_z = J_t: H_x is constant, (H_y, H_z) turns at Omega = H_x (1/J_x - 1/J_t)
  // (seed eqs. 3.20-3.23).
  const run::Trajectory& tr = r.trajectory;
  const double Jx = tr.J_B.front()(0, 0);
  const double Jt = tr.J_B.front()(1, 1);
  ASSERT_EQ(Jt, tr.J_B.front()(2, 2));
  const math::Vec3 H0 = tr.H_B.front();
  const double M = H0.norm();
  const double Omega = H0.x() * (1 / Jx - 1 / Jt);
  double err = 0.0;
  for (std::size_t i = 0; i < tr.size(); ++i) {
    const double a = -Omega * tr.time[i];
    const math::Vec3 exact(H0.x(), std::cos(a) * H0.y() - std::sin(a) * H0.z(),
                           std::sin(a) * H0.y() + std::cos(a) * H0.z());
    err = std::max(err, (tr.H_B[i] - exact).norm() / M);
  }
  EXPECT_LT(err, 1e-10);
  ::testing::Test::RecordProperty("half_open_max_rel_error", math::FormatNumber(err));
}

TEST(SeedSatelliteTest, OpenFlipsAtTheAnalyticPeriod) {
  const run::MissionResult r = run::RunMission(SeedConfiguration("open"));
  const run::Trajectory& tr = r.trajectory;
  const analysis::FreeBodySolution sol(math::InertiaTensor::FromMatrix(tr.J_B.front()),
                                       tr.H_B.front(), tr.q_NB.front(), 0.0);
  const std::vector<double> predicted = sol.FlipTimes(0.0, 40.0);
  ASSERT_EQ(r.flip_times.size(), predicted.size());
  ASSERT_GE(predicted.size(), 10u);  // the wing nut's moments: 11 flips in 40 s
  for (std::size_t i = 0; i < predicted.size(); ++i) {
    EXPECT_NEAR(r.flip_times[i], predicted[i], 5e-10);  // [s] measured 1.2e-10
  }
  for (std::size_t i = 1; i < r.flip_times.size(); ++i) {
    EXPECT_NEAR(r.flip_times[i] - r.flip_times[i - 1], sol.flip_half_period(),
                1.5e-10);  // [s] measured 3.2e-11
  }
}

// A deployment closed -> open over D seconds, with holds before and after.
schedule::Profile Deployment(double duration) {
  const std::string end = std::to_string(10.0 + duration);
  const std::string stop = std::to_string(20.0 + duration);
  return ProfileFromText("deploy",
                         "model: " + Models() +
                             "smallsat.yaml\nmode: geometry\ncoupling: exact\n"
                             "initial: {angular_velocity: [0.0091, 0.5235988, 0.0091]}\n"
                             "stages:\n  - {hold: closed, until: 10}\n"
                             "  - {to: open, law: minimum-jerk, until: " +
                             end +
                             "}\n"
                             "  - {hold: open, until: " +
                             stop +
                             "}\n"
                             "integrator: {method: rkmk-rkf78, rtol: 1.0e-11, atol: 1.0e-13}\n"
                             "output: {dt: 0.01}\n");
}

TEST(CouplingTest, RateErrorScalesWithHingeRateButAttitudeOffsetWithSwing) {
  // docs/design.md 2.5: quasi-rigid coupling (the seed's) errs in w in proportion to the hinge
  // rate, but the attitude offset accumulated by the end of deployment, int J^-1 h_rel dt,
  // is a geometric phase set by the total swing, not its speed.
  const run::CouplingComparison fast = run::CompareCouplings(Deployment(2.0));
  const run::CouplingComparison slow = run::CompareCouplings(Deployment(20.0));
  const double rate_ratio = fast.max_w_difference_deploying / slow.max_w_difference_deploying;
  EXPECT_GT(rate_ratio, 7.0);  // ~10 for a 10x slower deployment (measured 10.0)
  EXPECT_LT(rate_ratio, 13.0);
  EXPECT_GT(fast.attitude_offset_at_deployment_end, 0.1);  // it is not small: ~0.28 rad
  EXPECT_NEAR(fast.attitude_offset_at_deployment_end, slow.attitude_offset_at_deployment_end,
              0.02 * fast.attitude_offset_at_deployment_end);
  ::testing::Test::RecordProperty("w_diff_fast",
                                  math::FormatNumber(fast.max_w_difference_deploying));
  ::testing::Test::RecordProperty("w_diff_slow",
                                  math::FormatNumber(slow.max_w_difference_deploying));
  ::testing::Test::RecordProperty("offset_fast",
                                  std::to_string(fast.attitude_offset_at_deployment_end));
  ::testing::Test::RecordProperty("offset_slow",
                                  std::to_string(slow.attitude_offset_at_deployment_end));
}

TEST(CouplingTest, QuasiRigidConservesMomentumToo) {
  const run::CouplingComparison c = run::CompareCouplings(Deployment(5.0));
  EXPECT_LT(c.exact.max_h_N_drift, 1e-10);
  EXPECT_LT(c.quasi_rigid.max_h_N_drift, 1e-10);
}

// The streamed run is the in-memory run: the same samples, in blocks of at most
// kSampleBlock (memory bounded whatever the horizon), and the same analysis.
class BlockCounter final : public run::SampleSink {
 public:
  void Append(const run::Trajectory& b) override {
    ++blocks;
    largest = std::max(largest, b.size());
    for (std::size_t k = 0; k < b.size(); ++k) {
      time.push_back(b.time[k]);
      H_B.push_back(b.H_B[k]);
      if (!b.hinge_angles.empty()) hinges.push_back(b.hinge_angles[k]);
    }
  }
  std::size_t blocks = 0, largest = 0;
  std::vector<double> time;
  std::vector<math::Vec3> H_B;
  std::vector<Eigen::VectorXd> hinges;
};

TEST(MissionStreamTest, StreamedSamplesEqualTheInMemoryTrajectory) {
  for (const char* name : {"wing_nut.yaml", "smallsat_three_stage.yaml"}) {
    SCOPED_TRACE(name);
    schedule::Profile p =
        io::LoadProfile(std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/" + name);
    p.output.dt = p.t_end() / 10000.0;  // > 2 blocks, the last one partial
    const run::MissionResult whole = run::RunMission(p);
    BlockCounter sink;
    const run::MissionResult streamed = run::RunMission(p, sink);
    EXPECT_EQ(streamed.trajectory.size(), 0u) << "streamed runs keep no trajectory";
    EXPECT_GE(sink.blocks, 3u);
    EXPECT_EQ(sink.largest, run::kSampleBlock);
    EXPECT_EQ(sink.time, whole.trajectory.time);
    EXPECT_EQ(sink.H_B, whole.trajectory.H_B);
    EXPECT_EQ(sink.hinges, whole.trajectory.hinge_angles);
    EXPECT_EQ(streamed.flip_times, whole.flip_times);
    EXPECT_EQ(streamed.max_h_N_drift, whole.max_h_N_drift);
    ASSERT_EQ(streamed.danger_windows.size(), whole.danger_windows.size());
    for (std::size_t i = 0; i < whole.danger_windows.size(); ++i) {
      EXPECT_EQ(streamed.danger_windows[i].t_begin, whole.danger_windows[i].t_begin);
      EXPECT_EQ(streamed.danger_windows[i].t_end, whole.danger_windows[i].t_end);
    }
    ASSERT_EQ(streamed.stages.size(), whole.stages.size());
    for (std::size_t i = 0; i < whole.stages.size(); ++i) {
      EXPECT_EQ(streamed.stages[i].separatrix_distance, whole.stages[i].separatrix_distance);
      EXPECT_EQ(streamed.stages[i].observed_flips, whole.stages[i].observed_flips);
      EXPECT_EQ(streamed.stages[i].predicted_flips, whole.stages[i].predicted_flips);
    }
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim
