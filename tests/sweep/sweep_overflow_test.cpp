// Sweeps: every numeric key of a sweep file, given 1e308, -1e308, 1e154 or -1e154, is
// refused in one line (the file's rules, or the case's profile rules naming the case) or
// gives cases that compile (their runs bounded by the work estimate, as the profile
// overflow test runs them); and a case is validated and estimated once from its build to
// its outcome.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "deploysim/sweep/outcome.h"
#include "deploysim/sweep/sweep_file.h"
#include "deploysim/sweep/sweep_spec.h"
#include "numeric_keys.h"
#include "sweep_test_support.h"

namespace deploysim::sweep {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;

class SweepOverflowTest : public testing::SweepDirTest {
 protected:
  void SetUp() override {
    SweepDirTest::SetUp();
    for (const char* dir : {"deployment_profiles", "models", "sweeps"}) {
      fs::copy(fs::path(DEPLOYSIM_SOURCE_DIR) / dir, Path(dir), fs::copy_options::recursive);
    }
  }

  /// Reads the sweep and builds its cases (all of them up to `all`, else the first and
  /// the last); "" or the refusal.
  static std::string Outcome(const std::string& sweep, std::size_t all) {
    try {
      const SweepSpec spec = ReadSweep(sweep);
      const std::size_t n = spec.case_count();
      if (n <= all) {
        ValidateCases(spec);
      } else {
        BuildCase(spec, 0);
        BuildCase(spec, n - 1);
      }
      return "";
    } catch (const std::exception& e) {
      return e.what();
    }
  }

  int Mutate(const std::string& file, std::size_t all) {
    const std::string path = Path(file);
    return deploysim::testing::GiveEveryKeyExtremes(path, [&] { return Outcome(path, all); });
  }
};

TEST_F(SweepOverflowTest, GridSweepOfAHingeProfile) {
  std::printf("accepted: %d values\n", Mutate("sweeps/minor_axis_damper_spin.yaml", 100));
}

TEST_F(SweepOverflowTest, MonteCarloSweepWithFailureModes) {
  std::printf("accepted: %d values\n", Mutate("sweeps/smallsat_spring_stiffness_spin.yaml", 0));
}

TEST_F(SweepOverflowTest, ACaseIsValidatedAndEstimatedOnce) {
  for (const char* sweep :
       {"sweeps/smallsat_duration_spin.yaml", "sweeps/minor_axis_damper_spin.yaml"}) {
    const SweepSpec spec = ReadSweep(Path(sweep));
    const std::uint64_t v0 = schedule::ValidationCount();
    const std::uint64_t e0 = analysis::WorkEstimateCount();
    const Case c = BuildCase(spec, 0);
    EXPECT_EQ(schedule::ValidationCount() - v0, 1u) << sweep;
    EXPECT_EQ(analysis::WorkEstimateCount() - e0, 1u) << sweep;
    if (c.profile().is_hinge_profile()) continue;  // its run: 14 s (the io test runs one)
    const CaseOutcome o = SimulateOutcome(c, OutcomeSettings{});
    EXPECT_EQ(o.end_time, c.profile().t_end());
    EXPECT_EQ(schedule::ValidationCount() - v0, 1u) << sweep;
    EXPECT_EQ(analysis::WorkEstimateCount() - e0, 1u) << sweep;
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::sweep
