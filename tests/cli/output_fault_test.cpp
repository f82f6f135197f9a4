// Output under faults (issue 10): a full disk (a file size limit, RLIMIT_FSIZE, set in
// the child: no root needed), signals and kill -9 while `deploysim simulate` or `sweep`
// writes, a CSV that fails after the HDF5 file, and output names near NAME_MAX. In every
// case: a clear one-line error naming the file, a non-zero exit, no temporary left, an
// older file of the same name intact, and a sweep that --resume then finishes exactly.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "deploysim/io/trajectory_file.h"
#ifdef DEPLOYSIM_HAVE_SWEEP
#include "deploysim/sweep/results_file.h"
#endif
#include "temp_dir_test.h"

namespace deploysim {
namespace {

namespace fs = std::filesystem;

struct Child {
  pid_t pid = -1;
  int status = 0;
  bool exited() const { return WIFEXITED(status); }
  int code() const { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }
  bool signaled(int s) const { return WIFSIGNALED(status) && WTERMSIG(status) == s; }
};

std::string Slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

class OutputFaultTest : public testing::TempDirTest {
 protected:
  // Starts the CLI with `args` in the test folder; stdout and stderr go to files. A
  // `fsize_kb` > 0 sets RLIMIT_FSIZE (soft and hard, as `ulimit -f` does).
  Child Start(const std::vector<std::string>& args, long fsize_kb = 0) {
    Child c;
    const std::string out = Path("stdout.txt"), err = Path("stderr.txt");
    c.pid = ::fork();
    if (c.pid == 0) {
      if (::chdir(Path("").c_str()) != 0) ::_exit(126);
      const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(o, 1);
      ::dup2(e, 2);
      // A write past the limit then fails with EFBIG (the CLI ignores SIGXFSZ too).
      std::signal(SIGXFSZ, SIG_IGN);
      if (fsize_kb > 0) {
        const rlim_t bytes = static_cast<rlim_t>(fsize_kb) * 1024;
        const rlimit r{bytes, bytes};
        ::setrlimit(RLIMIT_FSIZE, &r);
      }
      std::vector<char*> argv;
      std::string cli = DEPLOYSIM_CLI;
      argv.push_back(cli.data());
      std::vector<std::string> copy = args;
      for (std::string& a : copy) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(cli.c_str(), argv.data());
      ::_exit(127);
    }
    return c;
  }
  Child Wait(Child c) {
    ::waitpid(c.pid, &c.status, 0);
    return c;
  }
  Child Run(const std::vector<std::string>& args, long fsize_kb = 0) {
    return Wait(Start(args, fsize_kb));
  }
  std::string Stderr() const { return Slurp(Path("stderr.txt")); }

  // Temporaries in the test folder (".NAME.PID.N.tmp" or a shortened form).
  std::vector<std::string> Temporaries() const {
    std::vector<std::string> t;
    for (const std::string& e : Entries()) {
      if (e.size() > 4 && e.front() == '.' && e.compare(e.size() - 4, 4, ".tmp") == 0) {
        t.push_back(e);
      }
    }
    return t;
  }
  // Waits (up to a minute: not a timing test) until a temporary of the run appears.
  bool WaitForTemporary() const {
    for (int i = 0; i < 6000; ++i) {
      if (!Temporaries().empty()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

  // The wing nut, `until` seconds sampled every `dt`.
  std::string Profile(const std::string& name, double until, double dt) {
    return Write(name, "name: " + name +
                           "\nmodel: " DEPLOYSIM_SOURCE_DIR
                           "/models/wing_nut.yaml\n"
                           "mode: tensor\ncoupling: quasi-rigid\n"
                           "initial:\n  attitude_wxyz: [1, 0, 0, 0]\n"
                           "  angular_momentum: [1.0e-8, 2.1252e-5, 1.0e-8]\n"
                           "stages:\n  - {name: free spin, hold: default, until: " +
                           std::to_string(until) +
                           "}\n"
                           "integrator:\n  method: rkmk-rkf78\n  rtol: 1.0e-12\n  atol: 1.0e-14\n"
                           "output:\n  dt: " +
                           std::to_string(dt) + "\n");
  }
  // A small sweep of the small satellite (12 cases).
  std::string Sweep() {
    return Write("sweep.yaml", "name: fault_sweep\nbase: " DEPLOYSIM_SOURCE_DIR
                               "/deployment_profiles/smallsat_three_stage.yaml\n"
                               "integrator:\n  method: exact\n  rtol: 1.0e-9\n  atol: 1.0e-11\n"
                               "grid:\n"
                               "  - {parameter: deploy_duration_scale, logspace: [0.1, 3, 4]}\n"
                               "  - {parameter: spin_rate_rpm, logspace: [0.2, 8, 3]}\n"
                               "outcome:\n  tumble_angle_deg: 20\n");
  }
  // One line, naming the file and the reason.
  void ExpectOneLineError(const std::string& file, const std::string& reason) const {
    const std::string err = Stderr();
    EXPECT_EQ(err.find('\n'), err.size() - 1) << err;
    EXPECT_NE(err.find("error: " + file), std::string::npos) << err;
    EXPECT_NE(err.find(reason), std::string::npos) << err;
  }
};

TEST_F(OutputFaultTest, SimulateOnAFullDiskKeepsTheOlderFile) {
  const std::string profile = Profile("p.yaml", 40, 0.01);
  const std::string old_text = "an older file of the same name";
  // Limits that stop the write at its start, in the samples, and near the end.
  for (long kb : {16L, 300L, 700L, 1000L, 1300L}) {
    SCOPED_TRACE("ulimit -f " + std::to_string(kb));
    Write("out.h5", old_text);
    const Child c = Run({"simulate", profile, "-o", "out.h5", "-q"}, kb);
    ASSERT_TRUE(c.exited()) << "killed by a signal: " << c.status;
    EXPECT_EQ(c.code(), 1);
    ExpectOneLineError("out.h5", "File too large");
    EXPECT_EQ(Slurp(Path("out.h5")), old_text);
    EXPECT_TRUE(Temporaries().empty());
  }
  // Without the limit the same run writes the file.
  const Child ok = Run({"simulate", profile, "-o", "out.h5", "-q"});
  EXPECT_EQ(ok.code(), 0) << Stderr();
  EXPECT_EQ(io::ReadTrajectoryFile(Path("out.h5")).trajectory.size(), 4001u);
}

TEST_F(OutputFaultTest, CsvFailingAfterTheHdf5FileReplacesNeither) {
  const std::string profile = Profile("p.yaml", 40, 0.005);
  ASSERT_EQ(Run({"simulate", profile, "-o", "ref.h5", "-q", "--csv"}).code(), 0) << Stderr();
  const auto h5 = static_cast<long>(fs::file_size(Path("ref.h5")));
  const auto csv = static_cast<long>(fs::file_size(Path("ref.h5.csv")));
  // Room for the HDF5 file (and its reserve), not for the CSV.
  const long kb = (h5 + csv) / 2 / 1024;
  ASSERT_GT(kb * 1024, h5 + (256 << 10) + (64 << 10));
  ASSERT_LT(kb * 1024, csv);
  Write("out.h5", "old h5");
  Write("out.h5.csv", "old csv");
  const Child c = Run({"simulate", profile, "-o", "out.h5", "-q", "--csv"}, kb);
  ASSERT_TRUE(c.exited()) << c.status;
  EXPECT_EQ(c.code(), 1);
  ExpectOneLineError("out.h5.csv", "File too large");
  EXPECT_EQ(Slurp(Path("out.h5")), "old h5") << "the HDF5 file was replaced without its CSV";
  EXPECT_EQ(Slurp(Path("out.h5.csv")), "old csv");
  EXPECT_TRUE(Temporaries().empty());
  // A CSV path that is a folder is refused before anything runs.
  fs::create_directory(Path("dir.h5.csv"));
  EXPECT_EQ(Run({"simulate", profile, "-o", "dir.h5", "-q", "--csv"}).code(), 1);
  EXPECT_FALSE(fs::exists(Path("dir.h5")));
  EXPECT_TRUE(Temporaries().empty());
}

TEST_F(OutputFaultTest, SigtermAndSigintWhileSimulatingLeaveNoTemporary) {
  const std::string profile = Profile("long.yaml", 20000, 0.01);  // minutes of work
  for (int sig : {SIGTERM, SIGINT}) {
    SCOPED_TRACE(sig);
    Write("out.h5", "older");
    Child c = Start({"simulate", profile, "-o", "out.h5", "-q", "--csv"});
    ASSERT_TRUE(WaitForTemporary());
    ::kill(c.pid, sig);
    c = Wait(c);
    EXPECT_TRUE(c.signaled(sig)) << c.status;  // the shell reports 128 + sig
    EXPECT_TRUE(Temporaries().empty());
    EXPECT_EQ(Slurp(Path("out.h5")), "older");
    EXPECT_FALSE(fs::exists(Path("out.h5.csv")));
  }
}

TEST_F(OutputFaultTest, KillMinus9WhileSimulatingIsCleanedByTheNextRun) {
  const std::string profile = Profile("long.yaml", 20000, 0.01);
  Write("out.h5", "older");
  Child c = Start({"simulate", profile, "-o", "out.h5", "-q", "--csv"});
  ASSERT_TRUE(WaitForTemporary());
  ::kill(c.pid, SIGKILL);
  c = Wait(c);
  EXPECT_TRUE(c.signaled(SIGKILL));
  EXPECT_EQ(Slurp(Path("out.h5")), "older");
  // The CSV's temporary is anonymous (O_TMPFILE): at most the HDF5 one is left, and the
  // next run of the same output removes it (its process is gone).
  EXPECT_LE(Temporaries().size(), 1u);
  const Child next = Run({"simulate", Profile("short.yaml", 1, 0.1), "-o", "out.h5", "-q"});
  EXPECT_EQ(next.code(), 0) << Stderr();
  EXPECT_TRUE(Temporaries().empty());
}

#ifdef DEPLOYSIM_HAVE_SWEEP
TEST_F(OutputFaultTest, SweepOnAFullDiskThenResumeEqualsAnUninterruptedRun) {
  const std::string sweep = Sweep();
  ASSERT_EQ(Run({"sweep", sweep, "-o", "ref.h5", "-q", "--threads", "2", "--csv"}).code(), 0)
      << Stderr();
  const sweep::SweepTable ref = sweep::ReadSweepResults(Path("ref.h5"));
  Write("out.h5", "older results");
  const long kb = static_cast<long>(fs::file_size(Path("ref.h5")) / 1024 / 2);
  const Child c = Run({"sweep", sweep, "-o", "out.h5", "-q", "--threads", "2", "--csv"}, kb);
  ASSERT_TRUE(c.exited()) << "killed by a signal: " << c.status;
  EXPECT_EQ(c.code(), 1);
  ExpectOneLineError("out.h5", "File too large");
  EXPECT_EQ(Slurp(Path("out.h5")), "older results");
  EXPECT_FALSE(fs::exists(Path("out.h5.csv")));
  EXPECT_TRUE(Temporaries().empty());
  ASSERT_TRUE(fs::exists(Path("out.h5.partial"))) << "the journal keeps the finished cases";
  const Child resumed =
      Run({"sweep", sweep, "-o", "out.h5", "-q", "--threads", "2", "--csv", "--resume"});
  EXPECT_EQ(resumed.code(), 0) << Stderr();
  const sweep::SweepTable got = sweep::ReadSweepResults(Path("out.h5"));
  EXPECT_EQ(got.columns, ref.columns);
  ASSERT_EQ(got.numbers.size(), ref.numbers.size());
  for (const auto& [name, column] : ref.numbers) {
    const std::vector<double>& g = got.numbers.at(name);
    ASSERT_EQ(g.size(), column.size()) << name;
    for (std::size_t i = 0; i < g.size(); ++i) {
      EXPECT_TRUE(g[i] == column[i] || (std::isnan(g[i]) && std::isnan(column[i])))
          << name << "[" << i << "]";  // bit for bit (or both none)
    }
  }
  EXPECT_EQ(got.texts, ref.texts);
  EXPECT_TRUE(fs::exists(Path("out.h5.csv")));
  EXPECT_FALSE(fs::exists(Path("out.h5.partial")));
  EXPECT_TRUE(Temporaries().empty());
}

TEST_F(OutputFaultTest, ResumeRemovesTheTemporaryOfAKilledFinalWrite) {
  const std::string sweep = Sweep();
  // A sweep killed (-9) in its final write: its journal and the temporary of a process
  // that is gone (the pid of a child that has exited).
  Child c = Start({"sweep", sweep, "-o", "out.h5", "-q", "--threads", "2"}, 64);
  c = Wait(c);
  ASSERT_EQ(c.code(), 1) << Stderr();  // the final write failed: the journal is complete
  ASSERT_TRUE(fs::exists(Path("out.h5.partial")));
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  const std::string stale = ".out.h5." + std::to_string(dead) + ".0.tmp";
  Write(stale, "half a results file");
  Write(".out.h5.csv." + std::to_string(dead) + ".3.tmp", "half a CSV");
  const Child resumed = Run({"sweep", sweep, "-o", "out.h5", "-q", "--csv", "--resume"});
  EXPECT_EQ(resumed.code(), 0) << Stderr();
  EXPECT_TRUE(Temporaries().empty());
  EXPECT_EQ(sweep::ReadSweepResults(Path("out.h5")).rows, 12u);
}

#endif  // DEPLOYSIM_HAVE_SWEEP

TEST_F(OutputFaultTest, OutputNamesUpTo255Characters) {
  const std::string profile = Profile("p.yaml", 1, 0.1);
  for (std::size_t length : {253u, 255u}) {
    const std::string name = std::string(length - 3, 'n') + ".h5";
    const Child c = Run({"simulate", profile, "-o", name, "-q"});
    EXPECT_EQ(c.code(), 0) << length << ": " << Stderr();
    EXPECT_EQ(io::ReadTrajectoryFile(Path(name)).trajectory.size(), 11u);
    EXPECT_TRUE(Temporaries().empty());
  }
  // 253 + ".csv" is too long for any file system: refused with the system's reason.
  const std::string name = std::string(250, 'c') + ".h5";
  const Child c = Run({"simulate", profile, "-o", name, "-q", "--csv"});
  EXPECT_EQ(c.code(), 1);
  EXPECT_NE(Stderr().find("File name too long"), std::string::npos) << Stderr();
  EXPECT_TRUE(Temporaries().empty());
}

}  // namespace
}  // namespace deploysim
