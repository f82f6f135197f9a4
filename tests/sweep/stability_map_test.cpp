// tools/plot_stability_map.py renders a results file of a small sweep (grid with Monte
// Carlo samples, a third grid axis held fixed) as a PNG: the flip map of a stage sweep
// and the hinge map (latch shock with its limit, tumble) of a sweep over a hinge profile,
// and the tumble map (the outcome, the time to tumble) of both.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "deploysim/sweep/runner.h"
#include "deploysim/sweep/sweep_file.h"
#include "sweep_test_support.h"

namespace deploysim::sweep {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using testing::SmallsatProfile;
using testing::SpringProfile;
using testing::SweepDirTest;

int Shell(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST_F(SweepDirTest, StabilityMapRendersAsPng) {
  if (Shell("/usr/bin/python3 -c 'import matplotlib, h5py, numpy' 2>/dev/null") != 0) {
    GTEST_SKIP() << "python3-matplotlib, python3-h5py or python3-numpy missing";
  }
  const SweepSpec spec =
      LoadSweep(Write("s.yaml", "name: map test\nbase: " + SmallsatProfile() + R"(
integrator: {method: exact, rtol: 1.0e-9, atol: 1.0e-11}
grid:
  - {parameter: deploy_duration_scale, logspace: [0.2, 2, 3]}
  - {parameter: spin_rate_rpm, logspace: [0.3, 3, 4]}
  - {parameter: coupling, values: [exact, quasi-rigid]}
monte_carlo:
  samples: 2
  seed: 1
  parameters:
    - {parameter: nutation_deg, uniform: [0.5, 2]}
)"));
  RunOptions o;
  o.output = Path("r.h5");
  ASSERT_TRUE(RunSweep(spec, o).complete);
  const std::string script = std::string(DEPLOYSIM_SOURCE_DIR) + "/tools/plot_stability_map.py";
  ASSERT_EQ(Shell("/usr/bin/python3 '" + script + "' '" + Path("r.h5") + "' -o '" +
                  Path("map.png") + "' --fix coupling=quasi-rigid > '" + Path("log") + "' 2>&1"),
            0);
  std::ifstream png(Path("map.png"), std::ios::binary);
  char magic[8] = {};
  png.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  EXPECT_GT(std::filesystem::file_size(Path("map.png")), 20000u);
  // A sweep without two grid axes is refused with a message.
  const SweepSpec one = LoadSweep(Write("one.yaml", "name: one\nbase: " + SmallsatProfile() +
                                                        "\ngrid:\n  - {parameter: spin_rate_rpm, "
                                                        "values: [1, 2]}\n"));
  o.output = Path("one.h5");
  ASSERT_TRUE(RunSweep(one, o).complete);
  EXPECT_NE(Shell("/usr/bin/python3 '" + script + "' '" + Path("one.h5") + "' > '" + Path("log") +
                  "' 2>&1"),
            0);
}

bool IsPng(const std::string& path) {
  std::ifstream png(path, std::ios::binary);
  char magic[8] = {};
  png.read(magic, 8);
  return std::string(magic + 1, 3) == "PNG" && std::filesystem::file_size(path) > 20000u;
}

TEST_F(SweepDirTest, HingeMapRendersAsPng) {
  if (Shell("/usr/bin/python3 -c 'import matplotlib, h5py, numpy' 2>/dev/null") != 0) {
    GTEST_SKIP() << "python3-matplotlib, python3-h5py or python3-numpy missing";
  }
  const SweepSpec spec =
      LoadSweep(Write("s.yaml", "name: hinge map test\nbase: " + SpringProfile() + R"(
integrator: {method: exact, rtol: 1.0e-9, atol: 1.0e-11}
grid:
  - {parameter: spring_stiffness, logspace: [0.2, 5, 3]}
  - {parameter: spin_rate_rpm, logspace: [0.5, 8, 3]}
monte_carlo:
  samples: 2
  seed: 3
  parameters:
    - {parameter: stick_fraction, panel: wing_plus_x, choice: [0, 0.7]}
outcome: {latch_shock_limit_deg_s: 15}
)"));
  RunOptions o;
  o.output = Path("r.h5");
  ASSERT_TRUE(RunSweep(spec, o).complete);
  const std::string script = std::string(DEPLOYSIM_SOURCE_DIR) + "/tools/plot_stability_map.py";
  const std::string run = "/usr/bin/python3 '" + script + "' '" + Path("r.h5") + "' -o ";
  ASSERT_EQ(Shell(run + "'" + Path("hinges.png") + "' > '" + Path("log") + "' 2>&1"), 0);
  EXPECT_TRUE(IsPng(Path("hinges.png")));
  // The flip map of the same sweep, and another shock limit.
  ASSERT_EQ(Shell(run + "'" + Path("flips.png") + "' --map flips > '" + Path("log") + "' 2>&1"), 0);
  EXPECT_TRUE(IsPng(Path("flips.png")));
  ASSERT_EQ(
      Shell(run + "'" + Path("limit.png") + "' --shock-limit 40 > '" + Path("log") + "' 2>&1"), 0);
  EXPECT_TRUE(IsPng(Path("limit.png")));
  // The tumble map: the outcome and the time to tumble.
  ASSERT_EQ(Shell(run + "'" + Path("tumble.png") + "' --map tumble > '" + Path("log") + "' 2>&1"),
            0);
  EXPECT_TRUE(IsPng(Path("tumble.png")));
  // A stage sweep has no latch columns: --map hinges is refused.
  const SweepSpec stage = LoadSweep(Write("t.yaml", "name: t\nbase: " + SmallsatProfile() + R"(
grid:
  - {parameter: spin_rate_rpm, values: [1, 2]}
  - {parameter: deploy_duration_scale, values: [1, 2]}
)"));
  o.output = Path("stage.h5");
  ASSERT_TRUE(RunSweep(stage, o).complete);
  EXPECT_NE(Shell("/usr/bin/python3 '" + script + "' '" + Path("stage.h5") + "' --map hinges > '" +
                  Path("log") + "' 2>&1"),
            0);
  // A missing file: one line, no traceback.
  EXPECT_NE(Shell("/usr/bin/python3 '" + script + "' '" + Path("missing.h5") + "' > '" +
                  Path("log") + "' 2>&1"),
            0);
  std::ifstream log(Path("log"));
  const std::string said((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(said.find("missing.h5: cannot open as HDF5"), std::string::npos) << said;
  EXPECT_EQ(said.find("Traceback"), std::string::npos) << said;
  // Its tumble map.
  ASSERT_EQ(Shell("/usr/bin/python3 '" + script + "' '" + Path("stage.h5") + "' -o '" +
                  Path("stage_tumble.png") + "' --map tumble > '" + Path("log") + "' 2>&1"),
            0);
  EXPECT_TRUE(IsPng(Path("stage_tumble.png")));
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::sweep
