// Hostile input files given to the `deploysim` command: a command-line file, a
// profile's `model:` or a sweep's `base:` that names a device, a FIFO or a file over the
// size limit; yaml-cpp 0.7's parser loop; alias chains and fan-outs; long values; text
// that is not UTF-8. Each ends at once with one line on stderr naming the file and the
// rule, a non-zero exit and no output file. The commands run under an address-space
// limit and a timeout, so that a regression fails the test instead of the machine.

#include <gtest/gtest.h>
#include <sys/stat.h>
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

using testing::CliRun;

class HostileInputTest : public testing::TempDirTest {
 protected:
  /// Runs `deploysim ARGS [< stdin_from]` with its memory bounded to 2 GiB (MemoryLimitPrefix) and
  /// `timeout` (a safety net that turns a hang into a failure: exit 124), capturing stderr.
  CliRun Run(const std::string& args, const std::string& stdin_from = "/dev/null") const {
    return testing::RunCliInShell(testing::MemoryLimitPrefix(2048) + "timeout -s KILL 120 ", args,
                                  Path("stderr.txt"), stdin_from);
  }

  /// `simulate FILE -o out.h5`: refused with one short line containing `part`.
  void ExpectSimulateRefused(const std::string& file,
                             const std::string& part,
                             const std::string& stdin_from = "/dev/null") const {
    const CliRun r = Run("simulate '" + file + "' -q -o '" + Path("out.h5") + "'", stdin_from);
    ExpectOneLine(r, part);
    EXPECT_FALSE(fs::exists(Path("out.h5")));
  }

  static void ExpectOneLine(const CliRun& r, const std::string& part) {
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.exit_code, 124) << "timed out";
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err.substr(0, 500);
    EXPECT_LT(r.err.size(), 700u) << r.err.substr(0, 800);
    EXPECT_NE(r.err.find(part), std::string::npos)
        << "expected '" << part << "' in: " << r.err.substr(0, 500);
  }

  /// A wing-nut profile (tensor model) with `model:` and the stage name replaced.
  std::string Profile(const std::string& model, const std::string& stage_name = "free spin") const {
    return "name: p\nmodel: " + model +
           "\ninitial: {angular_momentum: [1.0e-8, 2.1252e-5, 1.0e-8]}\n"
           "stages:\n  - {name: \"" +
           stage_name + "\", hold: default, until: 1}\n";
  }
  static std::string WingNutModel() {
    return std::string(DEPLOYSIM_SOURCE_DIR) + "/models/wing_nut.yaml";
  }
};

TEST_F(HostileInputTest, ACommaDoesNotMakeTheParserLoop) {
  for (const char* text : {",", "!,", "- ,", "a: ,", "name: p\n,\n"}) {
    SCOPED_TRACE(text);
    const std::string file = Write("c.yaml", text);
    ExpectSimulateRefused(file, "c.yaml: line ");
    const CliRun r = Run("simulate '" + file + "' -q -o '" + Path("out.h5") + "'");
    EXPECT_NE(r.err.find("YAML syntax error"), std::string::npos) << r.err;
  }
}

TEST_F(HostileInputTest, ModelThatIsADeviceOrFifoIsRefusedAtOnce) {
  ASSERT_EQ(::mkfifo(Path("fifo.yaml").c_str(), 0600), 0);
  for (const std::string& model :
       {std::string("/dev/zero"), std::string("/dev/urandom"), Path("fifo.yaml")}) {
    SCOPED_TRACE(model);
    const std::string profile = Write("p.yaml", Profile(model));
    ExpectSimulateRefused(profile, "p.yaml: model = " + model + ": cannot read ");
    const CliRun r = Run("simulate '" + profile + "' -q -o '" + Path("out.h5") + "'");
    EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
  }
  // /dev/stdin when stdin is a device (here /dev/zero).
  const std::string profile = Write("p.yaml", Profile("/dev/stdin"));
  ExpectSimulateRefused(profile, "is a character device, not a regular file", "/dev/zero");
}

TEST_F(HostileInputTest, CommandLineFileMustBeARegularFile) {
  ExpectSimulateRefused("/dev/stdin", "/dev/stdin: cannot read: is a character device",
                        "/dev/zero");
  ASSERT_EQ(::mkfifo(Path("fifo.yaml").c_str(), 0600), 0);
  ExpectSimulateRefused(Path("fifo.yaml"), "fifo.yaml: cannot read: is a FIFO");
  ExpectSimulateRefused(dir().string(), ": cannot read: is a directory");
  // Over the size limit (a valid profile padded with a comment).
  std::string big = Profile(WingNutModel()) + "#";
  big += std::string((std::size_t{1} << 20) + 1 - big.size(), 'x');
  ExpectSimulateRefused(Write("big.yaml", big),
                        "big.yaml: cannot read: the file has 1048577 bytes (input files have at "
                        "most 1048576 bytes, 1 MiB)");
}

TEST_F(HostileInputTest, SweepBaseThatIsADeviceOrFifoIsRefusedAtOnce) {
  ASSERT_EQ(::mkfifo(Path("fifo.yaml").c_str(), 0600), 0);
  for (const std::string& base : {std::string("/dev/urandom"), Path("fifo.yaml")}) {
    SCOPED_TRACE(base);
    const std::string sweep =
        Write("s.yaml", "name: s\nbase: " + base +
                            "\ngrid:\n  - {parameter: spin_rate_rpm, values: [1, 2]}\n");
    const CliRun r = Run("sweep '" + sweep + "' -q -o '" + Path("out.h5") + "'");
    ExpectOneLine(r, "s.yaml: base = " + base + ": cannot read ");
    EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(Path("out.h5")));
  }
}

TEST_F(HostileInputTest, AliasChainsAndFanOutsAreRefused) {
  std::string chain = Profile(WingNutModel()) + "x0: &x0 [1]\n";
  for (int i = 1; i <= 10000; ++i) {
    chain += "x" + std::to_string(i) + ": &x" + std::to_string(i) + " [*x" + std::to_string(i - 1) +
             "]\n";
  }
  ExpectSimulateRefused(Write("chain.yaml", chain), "nested more than 32 deep");
  std::string laughs = Profile(WingNutModel()) + "l0: &l0 [lol]\n";
  for (int i = 1; i <= 9; ++i) {
    laughs += "l" + std::to_string(i) + ": &l" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k) laughs += (k ? ", *l" : "*l") + std::to_string(i - 1);
    laughs += "]\n";
  }
  ExpectSimulateRefused(Write("laughs.yaml", laughs), "more than 100000 YAML nodes");
  ExpectSimulateRefused(Write("self.yaml", "a: &a [*a]\n"),
                        "an alias refers to a node that contains it");
}

TEST_F(HostileInputTest, LongValuesAreNotEchoedWhole) {
  const std::string mb(1000000, 'x');
  // A long name, a long number-like value, a long unknown key's value, a long model path.
  ExpectSimulateRefused(Write("name.yaml", "name: " + mb + "\nmodel: " + WingNutModel() + "\n"),
                        "name = xxxxxxxx");
  ExpectSimulateRefused(Write("until.yaml", Profile(WingNutModel()) + "output: {dt: 1" +
                                                std::string(999990, '0') + "x}\n"),
                        "output.dt = 1000");
  ExpectSimulateRefused(Write("key.yaml", Profile(WingNutModel()) + "extra: " + mb + "\n"),
                        "... (1000000 bytes): unknown key");
  ExpectSimulateRefused(Write("path.yaml", Profile(std::string(1000000, 'm'))),
                        "path.yaml: model = mmmm");
  ExpectSimulateRefused(Write("stage.yaml", Profile(WingNutModel(), mb)),
                        "stages[0].name = \"xxxx");
}

TEST_F(HostileInputTest, InvalidUtf8IsRefused) {
  ExpectSimulateRefused(Write("utf8.yaml", Profile(WingNutModel(), "spin \xff\xfe")),
                        "utf8.yaml: line 5, byte offset ");
  const CliRun r = Run("simulate '" + Path("utf8.yaml") + "' -q -o '" + Path("out.h5") + "'");
  EXPECT_NE(r.err.find("invalid UTF-8 (byte 0xff)"), std::string::npos) << r.err;
  ExpectSimulateRefused(Write("nul.yaml", Profile(WingNutModel(), "spin \\0")),
                        "control character 0x00");
}

// The valid profile still runs (the checks refuse only what they should).
TEST_F(HostileInputTest, AValidProfileNearTheLimitRuns) {
  std::string text = Profile(WingNutModel(), "caf\xc3\xa9 \xe2\x86\x92 spin");
  // Padded to just under 1 MiB with comment lines.
  while (text.size() + 81 < (std::size_t{1} << 20)) text += "#" + std::string(79, 'c') + "\n";
  const std::string file = Write("near.yaml", text);
  const CliRun r = Run("simulate '" + file + "' -q -o '" + Path("out.h5") + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(Path("out.h5")));
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim
