// "no hang, no abort, messages that blame the right file": runs the CLI (under
// `timeout`, so that a regression fails instead of hanging the suite) on inputs that used
// to hang, abort or blame the wrong file, and checks the one-line refusal.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_run.h"
#include "sanitizer_support.h"
#include "temp_dir_test.h"

namespace deploysim {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;

const std::string kSrc = DEPLOYSIM_SOURCE_DIR;
constexpr int kTimeoutExit = 124;  // timeout(1) when the limit is hit

using testing::CliRun;

class LimitsTest : public testing::TempDirTest {
 protected:
  // Runs `prefix deploysim args` under timeout 30 in a shell; prefix may set ulimits.
  CliRun Run(const std::string& args, const std::string& prefix = "") const {
    return testing::RunCliInShell(prefix + "timeout 30 ", args, Path("stderr.txt"));
  }

  // A wing-nut profile (tensors model) with the given stage end, method, output dt and
  // initial momentum.
  std::string WingNut(const std::string& name,
                      const std::string& until,
                      const std::string& method,
                      const std::string& dt,
                      const std::string& initial = "angular_momentum: [1.0e-8, 2.1252e-5, 1.0e-8]",
                      const std::string& model = "") const {
    const std::string m = model.empty() ? kSrc + "/models/wing_nut.yaml" : model;
    return Write(
        name, "name: " + name + "\nmodel: " + m +
                  "\nmode: tensor\ncoupling: quasi-rigid\ninitial:\n"
                  "  attitude_wxyz: [1, 0, 0, 0]\n  " +
                  initial + "\nstages:\n  - {name: free spin, hold: default, until: " + until +
                  "}\nintegrator:\n  method: " + method +
                  "\n  rtol: 1.0e-12\n  atol: 1.0e-14\n  step: 0.001\noutput:\n  dt: " + dt + "\n");
  }

  // The optional subcommands (sweep, crosscheck) are in this build.
  bool Has(const std::string& subcommand) const {
    return Run(subcommand + " --help").exit_code == 0;
  }

  static void ExpectOneLine(const CliRun& r, const std::string& must_contain) {
    EXPECT_NE(r.exit_code, 0) << r.err;
    EXPECT_NE(r.exit_code, kTimeoutExit) << "timed out";
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_LT(r.err.size(), 400u) << r.err;
    EXPECT_NE(r.err.find(must_contain), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("terminate"), std::string::npos) << r.err;
  }
};

// Hung: the exact flow takes 8 steps per period (1e15 s: ~1e15 steps); refused up front.
TEST_F(LimitsTest, HugeUntilWithExactIsRefusedUpFront) {
  for (const auto& [until, dt] :
       {std::pair<std::string, std::string>{"1e15", "1e9"}, {"1e300", "1e295"}}) {
    const std::string p = WingNut("until_" + until + ".yaml", until, "exact", dt);
    for (const std::string& args :
         {"simulate '" + p + "' -q -o '" + Path("o.h5") + "'", "analyze '" + p + "'"}) {
      SCOPED_TRACE(args);
      const CliRun r = Run(args);
      ExpectOneLine(r, p + ": the run asks for up to ");
      EXPECT_NE(r.err.find("turns"), std::string::npos) << r.err;
    }
  }
  EXPECT_FALSE(fs::exists(Path("o.h5")));
}

// Hung: 1e12 rad/s on the wing nut (every method resolves ~1e12 turns in 40 s).
TEST_F(LimitsTest, HugeSpinIsRefusedUpFront) {
  const std::string p =
      WingNut("spin.yaml", "40", "rkmk-rkf78", "0.01", "angular_velocity: [1e4, 1e12, 1e4]");
  ExpectOneLine(Run("simulate '" + p + "' -q -o '" + Path("o.h5") + "'"), p + ": the run asks");
}

// Hung: a rod-like inertia 1e-12 : 1 : 1 with momentum off its axes spins at ~1e12 rad/s;
// the same rod tumbling end over end at 1 rad/s runs (the bound on the first stage is
// the largest |w| on the energy ellipsoid, not |H|/I_min).
TEST_F(LimitsTest, RodLikeInertia) {
  const std::string model = Write("rod.yaml",
                                  "name: rod\nkind: tensors\nconfigurations:\n  default:\n"
                                  "    principal_moments: [1e-12, 1, 1]\n");
  const std::string fast =
      WingNut("rod_fast.yaml", "40", "exact", "0.01", "angular_momentum: [1, 1, 0.5]", model);
  ExpectOneLine(Run("analyze '" + fast + "'"), fast + ": the run asks");
  const std::string slow =
      WingNut("rod_slow.yaml", "40", "exact", "0.01", "angular_momentum: [0, 1, 0]", model);
  const CliRun ok = Run("analyze '" + slow + "'");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

// Was "FreeBodySolution::FlipTimes: [0, 40] s holds 5.34e+11 flips" (no file): a coarse
// fixed step ran quickly, then the stage report listed the flips. Now refused up front.
TEST_F(LimitsTest, FlipCountErrorNamesTheFile) {
  const std::string p =
      WingNut("spin_rk4.yaml", "40", "rk4", "0.01", "angular_velocity: [1e4, 1e12, 1e4]");
  const CliRun r = Run("analyze '" + p + "' --step 1");
  ExpectOneLine(r, p + ": ");
  EXPECT_EQ(r.err.find("FreeBodySolution"), std::string::npos) << r.err;
}

// A fixed-step run past the integrator's step limit: refused up front.
TEST_F(LimitsTest, TooManyFixedStepsIsRefused) {
  const std::string p = WingNut("steps.yaml", "40", "rk4", "0.01");
  ExpectOneLine(Run("analyze '" + p + "' --step 1e-7"), "integrator.step = 1e-07: gives 4e+08");
}

// A sweep whose cases spin too fast: refused when the cases are validated (before any
// runs), naming the sweep file and the case.
TEST_F(LimitsTest, SweepCaseOverTheLimitIsRefusedAtLoad) {
  if (!Has("sweep")) GTEST_SKIP() << "built without the sweep";
  const std::string s =
      Write("fast.yaml", "name: fast\nbase: " + kSrc +
                             "/deployment_profiles/smallsat_three_stage.yaml\n"
                             "grid:\n  - {parameter: spin_rate_rpm, logspace: [1, 1e9, 3]}\n"
                             "outcome:\n  tumble_angle_deg: 20\n");
  const CliRun r = Run("sweep '" + s + "' -q -o '" + Path("map.h5") + "'");
  ExpectOneLine(r, s + ": case ");
  EXPECT_NE(r.err.find("turns"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(Path("map.h5.partial")));
}

// Was blamed on the profile ("initial: zero angular momentum"): the model file is named.
TEST_F(LimitsTest, HugeHingePointBlamesTheModel) {
  std::ifstream in(kSrc + "/models/smallsat.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "hinge_point: [0.3, 0, 0.4]";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), "hinge_point: [1e200, 0, 0]");
  const std::string model = Write("models/smallsat.yaml", text);
  std::ifstream pin(kSrc + "/deployment_profiles/smallsat_three_stage.yaml");
  const std::string ptext((std::istreambuf_iterator<char>(pin)), std::istreambuf_iterator<char>());
  const std::string p = Write("profiles/p.yaml", ptext);
  const CliRun r = Run("analyze '" + p + "'");
  ExpectOneLine(r, model + ": panels[0] (wing_plus_x).hinge_point");
  EXPECT_NE(r.err.find("rule: |component| <= 1e+06 m"), std::string::npos) << r.err;
}

// CLI11's messages were two lines with a 300-digit bound: one short line naming the
// option and the value.
TEST_F(LimitsTest, OptionErrorsAreOneLine) {
  if (!Has("sweep") || !Has("crosscheck")) GTEST_SKIP() << "built without sweep or crosscheck";
  const std::string wn = "'" + kSrc + "/deployment_profiles/wing_nut.yaml'";
  const std::string sw =
      "'" + kSrc + "/sweeps/smallsat_duration_spin.yaml' -o '" + Path("map.h5") + "'";
  const std::string o = " -o '" + Path("o.h5") + "'";
  const std::pair<std::string, std::string> cases[] = {
      {"sweep " + sw + " --threads -1", "--threads: -1 is not an integer in [0, 256]"},
      {"sweep " + sw + " --threads abc", "--threads: abc is not an integer"},
      {"sweep " + sw + " --threads 100000", "--threads: 100000 is not an integer in [0, 256]"},
      {"simulate " + wn + o + " --dt 1e-5x", "--dt: 1e-5x is not a number > 0"},
      {"simulate " + wn + o + " --rtol -1", "--rtol: -1: must be in [1e-14, 0.001]"},
      {"simulate " + wn + o + " --step -2", "--step: -2: must be >= 0 (0: automatic)"},
      {"simulate " + wn + o + " --atol x", "--atol: x is not a number"},
      {"crosscheck " + wn + o + " --accuracy 5", "--accuracy: 5 is not a number in [1e-16, 0.1]"},
      {"crosscheck " + wn + o + " --until 1e300", "crosscheck end time 1e+300 s: must lie in"},
      {"crosscheck " + wn + o + " --until 1e999", "--until: 1e999 is not a number"},
      {"simulate " + wn + o + " --bogus", "--bogus"},
      {"simulate " + wn + o + " --dt", "--dt"},
  };
  for (const auto& [args, msg] : cases) {
    SCOPED_TRACE(args);
    const CliRun r = Run(args);
    ExpectOneLine(r, msg);
    EXPECT_EQ(r.exit_code, 1);  // bad input, as every other (not CLI11's own codes)
    EXPECT_EQ(r.err.find("179769313486"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(Path("o.h5")));
  EXPECT_FALSE(fs::exists(Path("map.h5.partial")));
}

// Was std::terminate (or a bare "Resource temporarily unavailable"): threads that cannot
// be created under an address-space limit are a one-line error naming the output; the
// journal stays consistent and --resume finishes the sweep.
TEST_F(LimitsTest, ThreadsThatCannotStartAreAnErrorAndResumeWorks) {
  if (!Has("sweep")) GTEST_SKIP() << "built without the sweep";
  if (deploysim::testing::kAddressSanitizer) {
    GTEST_SKIP() << "needs ulimit -v, under which AddressSanitizer cannot start";
  }
  const std::string sweep =
      "'" + kSrc + "/sweeps/smallsat_duration_spin.yaml' -q -o '" + Path("map.h5") + "'";
  // 256 threads of 8 MiB stacks need 2 GiB of address space: more than the 1 GiB allowed.
  const CliRun r = Run("sweep " + sweep + " --threads 256", "ulimit -s 8192; ulimit -v 1048576; ");
  ExpectOneLine(r, Path("map.h5") + ": cannot start worker thread");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_FALSE(fs::exists(Path("map.h5")));
  const CliRun resumed = Run("sweep " + sweep + " --threads 2 --resume");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_TRUE(fs::exists(Path("map.h5")));
  EXPECT_FALSE(fs::exists(Path("map.h5.partial")));
}

// Was: every case computed before the write failed. The destination is checked first.
TEST_F(LimitsTest, SweepOutputFolderIsCheckedBeforeAnyCase) {
  if (!Has("sweep")) GTEST_SKIP() << "built without the sweep";
  const std::string sweep = "'" + kSrc + "/sweeps/smallsat_duration_spin.yaml' -q -o ";
  const CliRun missing = Run("sweep " + sweep + "'" + Path("nope/map.h5") + "'");
  ExpectOneLine(missing, Path("nope/map.h5") + ": the output's folder");
  fs::create_directories(Path("folder"));
  const CliRun folder = Run("sweep " + sweep + "'" + Path("folder") + "'");
  ExpectOneLine(folder, Path("folder"));
  EXPECT_TRUE(fs::is_empty(Path("folder")));
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim
