// Every numeric rule holds for every value it can be given: each numeric key of shipped
// profiles and their models, given 1e308, -1e308, 1e154 and -1e154 (where squares and
// products overflow), is refused in one line or compiles to a run that finishes; a value
// the rules let through must never reach the run as inf or NaN and hang it.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/run/mission.h"
#include "deploysim/io/yaml_loader.h"
#include "numeric_keys.h"
#include "temp_dir_test.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;

class OverflowTest : public testing::TempDirTest {
 protected:
  /// The profile and its model copied into the test's directory, as in the repository.
  void SetUp() override {
    TempDirTest::SetUp();
    for (const char* dir : {"deployment_profiles", "models"}) {
      fs::copy(fs::path(DEPLOYSIM_SOURCE_DIR) / dir, Path(dir), fs::copy_options::recursive);
    }
  }

  /// Loads and compiles the profile; if accepted, runs it (its first `until` seconds when
  /// given: the long examples). Returns "" or the refusal.
  static std::string Outcome(const std::string& profile, std::optional<double> until) {
    try {
      std::shared_ptr<const run::CompiledRun> run = LoadRun(profile);
      if (until) {
        ProfileOverrides o;
        o.until = run->profile().t_begin() + *until;
        run = LoadRun(profile, o);
      }
      run::NullSink sink;
      run::RunOptions o;
      o.sample_trajectory = false;
      const run::MissionResult r = run::RunMission(*run, sink, {}, o);
      EXPECT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
      return "";
    } catch (const std::exception& e) {
      return e.what();
    }
  }

  /// Gives every numeric key of `file` (relative to the copy) each extreme value in turn;
  /// runs `profile` each time. Returns how many were accepted and ran.
  int Mutate(const std::string& file,
             const std::string& profile,
             std::optional<double> until = std::nullopt) {
    return testing::GiveEveryKeyExtremes(Path(file), [&] { return Outcome(Path(profile), until); });
  }
};

TEST_F(OverflowTest, HingeProfileAndModel) {
  const std::string profile = "deployment_profiles/smallsat_spring_deploy.yaml";
  const int a = Mutate(profile, profile);
  const int b = Mutate("models/smallsat.yaml", profile);
  std::printf("accepted and ran: %d profile values, %d model values\n", a, b);
}

TEST_F(OverflowTest, StageProfileAndTensorModel) {
  const std::string profile = "deployment_profiles/seed_satellite.yaml";
  const int a = Mutate(profile, profile);
  const int b = Mutate("models/seed_satellite.yaml", profile);
  std::printf("accepted and ran: %d profile values, %d model values\n", a, b);
}

TEST_F(OverflowTest, GeometryStagesRotorPendulumAndSlosh) {
  // The rotor, the flat spin and the tank run for minutes of their time: their first 5 s
  // run (a rotor turned across the spin by its hinge axis takes 40 s for the whole run).
  struct Case {
    const char* profile;
    const char* model;
    std::optional<double> until;
  };
  const Case cases[] = {
      {"deployment_profiles/smallsat_three_stage.yaml", nullptr, std::nullopt},
      {"deployment_profiles/dual_spin_rotor.yaml", "models/dual_spin.yaml", 5.0},
      {"deployment_profiles/minor_axis_flat_spin.yaml", "models/minor_axis_spinner.yaml", 5.0},
      {"deployment_profiles/spin_stabilized_tank.yaml", "models/spin_stabilized_tank.yaml", 5.0}};
  for (const Case& c : cases) {
    const int a = Mutate(c.profile, c.profile, c.until);
    const int b = c.model != nullptr ? Mutate(c.model, c.profile, c.until) : 0;
    std::printf("%s: accepted and ran %d profile values, %d model values\n", c.profile, a, b);
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
