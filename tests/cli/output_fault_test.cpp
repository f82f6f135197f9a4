// Output under faults: a full disk (a file size limit, RLIMIT_FSIZE, set in
// the child: no root needed), signals and kill -9 while `deploysim simulate` or `sweep`
// writes, a CSV that fails after the HDF5 file, and output names near NAME_MAX. In every
// case: a clear one-line error naming the file, a non-zero exit, no temporary left, an
// older file of the same name intact, and a sweep that --resume then finishes exactly.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/inotify.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "deploysim/io/trajectory_file.h"
#ifdef DEPLOYSIM_HAVE_SWEEP
#include "deploysim/sweep/results_file.h"
#endif
#include "temp_dir_test.h"

namespace deploysim {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;

struct Child {
  pid_t pid = -1;
  int status = 0;
  bool exited() const { return WIFEXITED(status); }
  int code() const { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }
  bool signaled(int s) const { return WIFSIGNALED(status) && WTERMSIG(status) == s; }
};

/// What the program does to the test folder and to the files it reads, as the kernel
/// reports it (inotify), and whether the program has ended (a pidfd): a test waits for
/// the event itself, never by sleeping or polling against a deadline that a busy machine
/// can miss.
class Watch {
 public:
  Watch() : fd_(::inotify_init1(IN_CLOEXEC)) {}
  ~Watch() {
    if (fd_ >= 0) ::close(fd_);
  }
  Watch(const Watch&) = delete;
  Watch& operator=(const Watch&) = delete;

  /// Watches `path` (a folder: the events of its entries; a file: its own events);
  /// returns the watch descriptor that events carry.
  int Add(const std::string& path, std::uint32_t mask) {
    const int wd = fd_ >= 0 ? ::inotify_add_watch(fd_, path.c_str(), mask) : -1;
    EXPECT_GE(wd, 0) << path << ": " << std::strerror(errno);
    return wd;
  }

  /// An event: its watch descriptor, kind (IN_*) and entry name (empty for the events of
  /// a watched file itself).
  using Match = std::function<bool(int wd, std::uint32_t mask, const std::string& name)>;

  /// Blocks until an event satisfying `match` arrives, or until the process `pid` ends
  /// first. True for the event. Two minutes without either is a failure of the program,
  /// not a busy machine (the runs here take well under a second).
  bool WaitFor(pid_t pid, const Match& match) {
    const int pidfd = static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
    EXPECT_GE(pidfd, 0) << std::strerror(errno);
    bool found = false;
    bool ended = false;
    alignas(inotify_event) char buffer[64 * 1024];
    while (!found && !ended) {
      pollfd fds[2] = {{fd_, POLLIN, 0}, {pidfd, POLLIN, 0}};
      const int n = ::poll(fds, 2, 120'000);
      if (n == 0) {
        ADD_FAILURE() << "no event and no end of process " << pid << " in two minutes";
        break;
      }
      if (n < 0) {
        if (errno == EINTR) continue;
        ADD_FAILURE() << "poll: " << std::strerror(errno);
        break;
      }
      if (fds[0].revents & POLLIN) {
        const ssize_t len = ::read(fd_, buffer, sizeof buffer);
        for (ssize_t at = 0; at < len && !found;) {
          const auto* e = reinterpret_cast<const inotify_event*>(buffer + at);
          const std::string name = e->len > 0 ? std::string(e->name) : std::string();
          found = match(e->wd, e->mask, name);
          at += static_cast<ssize_t>(sizeof(inotify_event) + e->len);
        }
      }
      ended = !found && (fds[1].revents & POLLIN) != 0;
    }
    if (pidfd >= 0) ::close(pidfd);
    return found;
  }

 private:
  int fd_;
};

bool IsTemporary(const std::string& e) {
  return e.size() > 4 && e.front() == '.' && e.compare(e.size() - 4, 4, ".tmp") == 0;
}

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
      if (IsTemporary(e)) t.push_back(e);
    }
    return t;
  }
  // Starts the CLI and returns once its first temporary exists (the kernel's event).
  Child StartAndWaitForTemporary(const std::vector<std::string>& args) {
    Watch w;
    w.Add(Path(""), IN_CREATE);
    Child c = Start(args);
    EXPECT_TRUE(w.WaitFor(
        c.pid, [](int, std::uint32_t, const std::string& name) { return IsTemporary(name); }))
        << "no temporary: " << Stderr();
    return c;
  }

  // The wing nut, `until` seconds sampled every `dt`.
  std::string Profile(const std::string& name,
                      double until,
                      double dt,
                      const std::string& model = DEPLOYSIM_SOURCE_DIR "/models/wing_nut.yaml") {
    return Write(name, "name: " + name + "\nmodel: " + model +
                           "\n"
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
    Child c = StartAndWaitForTemporary({"simulate", profile, "-o", "out.h5", "-q", "--csv"});
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
  Child c = StartAndWaitForTemporary({"simulate", profile, "-o", "out.h5", "-q", "--csv"});
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

// SIGINT and SIGTERM at many instants of a run's life, each found by the kernel's event
// (not by a delay): at its start, as it opens the profile, as it opens the model, when
// its first temporary appears, after the k-th write of the samples, and when the HDF5
// file is renamed into place. Whenever the signal lands: no temporary is left, and the
// HDF5 file and its CSV are either both the older files or both complete new ones.
TEST_F(OutputFaultTest, SignalsAtEveryMomentOfARunLeaveNoStrayFileAndNoHalfUpdate) {
  enum Moment { kStart, kProfileOpened, kModelOpened, kFirstTemporary, kSampleWrite, kRenamed };
  const char* moment_names[] = {"start",           "profile opened", "model opened",
                                "first temporary", "sample write",   "HDF5 file renamed"};
  fs::copy_file(DEPLOYSIM_SOURCE_DIR "/models/wing_nut.yaml", Path("model.yaml"));
  const std::string profile = Profile("p.yaml", 2, 0.001, Path("model.yaml"));
  constexpr std::size_t kSamples = 2001;
  constexpr int kRunsPerMoment = 34;  // 6 moments: 204 runs, half SIGINT, half SIGTERM
  int interrupted = 0, finished = 0, replaced = 0;
  for (int run = 0; run < 6 * kRunsPerMoment; ++run) {
    const Moment moment = static_cast<Moment>(run % 6);
    const int sig = (run / 6) % 2 == 0 ? SIGTERM : SIGINT;
    const int kth_write = 1 + (run / 12) % 16;
    SCOPED_TRACE(std::string(moment_names[moment]) + ", signal " + std::to_string(sig) +
                 ", write " + std::to_string(kth_write));
    Write("out.h5", "older h5");
    Write("out.h5.csv", "older csv");
    Watch w;
    const int folder = w.Add(Path(""), IN_CREATE | IN_MODIFY | IN_MOVED_TO);
    const int profile_wd = w.Add(profile, IN_OPEN);
    const int model_wd = w.Add(Path("model.yaml"), IN_OPEN);
    int writes = 0;
    const Watch::Match match = [&](int wd, std::uint32_t mask, const std::string& name) {
      switch (moment) {
        case kProfileOpened:
          return wd == profile_wd;
        case kModelOpened:
          return wd == model_wd;
        case kFirstTemporary:
          return wd == folder && (mask & IN_CREATE) && IsTemporary(name);
        case kSampleWrite:
          return wd == folder && (mask & IN_MODIFY) && IsTemporary(name) && ++writes == kth_write;
        case kRenamed:
          return wd == folder && (mask & IN_MOVED_TO) && name == "out.h5";
        default:
          return true;
      }
    };
    Child c = Start({"simulate", profile, "-o", "out.h5", "-q", "--csv"});
    const bool reached = moment == kStart || w.WaitFor(c.pid, match);
    ::kill(c.pid, sig);
    c = Wait(c);
    const bool done = c.exited() && c.code() == 0;
    ASSERT_TRUE(done || c.signaled(sig)) << "status " << c.status << ": " << Stderr();
    done ? ++finished : ++interrupted;
    ASSERT_TRUE(Temporaries().empty());
    const std::string h5 = Slurp(Path("out.h5"));
    const std::string csv = Slurp(Path("out.h5.csv"));
    if (h5 == "older h5") {
      EXPECT_FALSE(done);
      EXPECT_EQ(csv, "older csv") << "the CSV was replaced without its HDF5 file";
      // Once the HDF5 file has been renamed into place, the CSV follows it.
      EXPECT_FALSE(moment == kRenamed && reached);
    } else {
      ++replaced;
      EXPECT_NE(csv, "older csv") << "the HDF5 file was replaced without its CSV";
      EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), kSamples + 1);
      EXPECT_EQ(io::ReadTrajectoryFile(Path("out.h5")).trajectory.size(), kSamples);
    }
  }
  std::printf("%d runs: %d ended by the signal, %d finished first; %d wrote new outputs\n",
              6 * kRunsPerMoment, interrupted, finished, replaced);
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

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim
