// A run validates its profile once and estimates its work once, from the file to the
// trajectory written (what `deploysim simulate` does), and its result refers to the
// compiled run instead of holding a copy of the profile.

#include "deploysim/run/compiled_run.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "deploysim/run/mission.h"
#include "deploysim/io/trajectory_file.h"
#include "deploysim/io/yaml_loader.h"
#include "temp_dir_test.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

class CompiledRunTest : public testing::TempDirTest {
 protected:
  /// Loads `profile` with overrides, runs it into a trajectory file; expects one
  /// validation and one work estimate in all.
  void ExpectOnce(const std::string& profile, const ProfileOverrides& o) {
    const std::uint64_t v0 = schedule::ValidationCount();
    const std::uint64_t e0 = analysis::WorkEstimateCount();
    const std::shared_ptr<const run::CompiledRun> run =
        LoadRun(std::string(DEPLOYSIM_SOURCE_DIR) + "/" + profile, o);
    TrajectoryOutputs out(Path("run.h5"), Path("run.h5.csv"), run->profile());
    const run::MissionResult r = run::RunMission(*run, out);
    out.Finish(r);
    out.Commit();
    EXPECT_EQ(schedule::ValidationCount() - v0, 1u) << profile;
    EXPECT_EQ(analysis::WorkEstimateCount() - e0, 1u) << profile;
    // The result refers to the run it came from: no copy of the profile.
    EXPECT_EQ(r.run.get(), run.get());
    EXPECT_EQ(&r.profile(), &run->profile());
    EXPECT_EQ(&r.run->work(), &run->work());
  }
};

TEST_F(CompiledRunTest, AStageProfileIsValidatedAndEstimatedOnce) {
  ProfileOverrides o;
  o.until = 80.0;
  o.output_dt = 0.5;
  ExpectOnce("deployment_profiles/seed_satellite.yaml", o);
}

TEST_F(CompiledRunTest, AHingeProfileIsValidatedAndEstimatedOnce) {
  ProfileOverrides o;
  o.until = 70.0;
  o.rtol = 1e-9;
  ExpectOnce("deployment_profiles/smallsat_spring_deploy.yaml", o);
}

TEST_F(CompiledRunTest, ASpinIsResolvedOnceAtCompile) {
  // An initial spin given as axis, rate and nutation: the compiled run's profile carries
  // the momentum it resolves to, the same as the profile reader's.
  std::ifstream in(std::string(DEPLOYSIM_SOURCE_DIR) +
                   "/deployment_profiles/smallsat_spring_deploy.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t w = text.find("  angular_velocity:");
  ASSERT_NE(w, std::string::npos);
  text.replace(w, text.find('\n', w) - w, "  spin: {axis: y, rate_rpm: 5, nutation_deg: 1.4}");
  const std::size_t m = text.find("../models/");
  ASSERT_NE(m, std::string::npos);
  text.replace(m, 2, DEPLOYSIM_SOURCE_DIR);
  const std::string path = Write("spin.yaml", text);
  const std::uint64_t v0 = schedule::ValidationCount();
  const auto run = LoadRun(path);
  EXPECT_EQ(schedule::ValidationCount() - v0, 1u);
  ASSERT_TRUE(run->profile().initial.spin.has_value());
  ASSERT_TRUE(run->profile().initial.H_B.has_value());
  EXPECT_EQ(*run->profile().initial.H_B, *LoadProfile(path).initial.H_B);  // bit for bit
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
