// Running sweeps (sweep/runner.h): bit-identical results whatever the thread count and
// against an MPI run with 2 ranks; an interrupted sweep (cancelled, or killed outright
// with SIGKILL) resumes without repeating or losing a case; the journal's safeguards.

#include "deploysim/sweep/runner.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "deploysim/sweep/journal.h"
#include "deploysim/sweep/mpi_session.h"
#include "deploysim/sweep/parallel.h"
#include "deploysim/sweep/sweep_file.h"
#include "sweep_test_support.h"

namespace deploysim::sweep {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;
using testing::ExpectSameCases;
using testing::SmallsatProfile;
using testing::SpringProfile;
using testing::SweepDirTest;

/// A sweep over the small satellite with grid and Monte Carlo parameters:
/// grid x grid x samples cases.
std::string SweepText(int grid, int samples) {
  return "name: runner test\nbase: " + SmallsatProfile() + R"(
integrator: {method: exact, rtol: 1.0e-9, atol: 1.0e-11}
grid:
  - {parameter: deploy_duration_scale, logspace: [0.2, 3, )" +
         std::to_string(grid) + R"(]}
  - {parameter: spin_rate_rpm, linspace: [2, 9, )" +
         std::to_string(grid) + R"(]}
monte_carlo:
  samples: )" +
         std::to_string(samples) + R"(
  seed: 20240611
  parameters:
    - {parameter: nutation_deg, uniform: [0.2, 4]}
    - {parameter: panel_mass_scale, panel: wing_minus_x, normal: {mean: 1, sigma: 0.03, min: 0.9, max: 1.1}}
    - {parameter: law, choice: [smoothstep, minimum-jerk]}
)";
}

/// A sweep over the spring deployment (a hinge profile) with failure modes:
/// grid x grid x samples cases.
std::string HingeSweepText(int grid, int samples) {
  return "name: hinge runner test\nbase: " + SpringProfile() + R"(
integrator: {method: exact, rtol: 1.0e-9, atol: 1.0e-11}
grid:
  - {parameter: spring_stiffness, logspace: [0.3, 3, )" +
         std::to_string(grid) + R"(]}
  - {parameter: spin_rate_rpm, linspace: [1, 8, )" +
         std::to_string(grid) + R"(]}
monte_carlo:
  samples: )" +
         std::to_string(samples) + R"(
  seed: 78
  parameters:
    - {parameter: nutation_deg, uniform: [0.2, 3]}
    - {parameter: stick_fraction, panel: wing_plus_x, choice: [0, 0.8], weights: [0.8, 0.2]}
    - {parameter: latch_fails, panel: wing_minus_x, choice: [no, yes], weights: [0.7, 0.3]}
    - {parameter: release_delay, panel: wing_minus_x, uniform: [0, 20]}
outcome: {latch_shock_limit_deg_s: 15}
)";
}

RunOptions Options(const std::string& output, int threads) {
  RunOptions o;
  o.output = output;
  o.threads = threads;
  return o;
}

/// Case indices of a journal.
std::vector<std::size_t> JournalIndices(const std::string& path, const SweepSpec& spec) {
  std::vector<std::size_t> v;
  for (const auto& r : ReadJournal(path, Fingerprint(spec), spec.case_count()).records) {
    v.push_back(r.first);
  }
  return v;
}

TEST_F(SweepDirTest, ResultsAreBitIdenticalForOneTwoAndFourThreads) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", SweepText(5, 8)));  // 200 cases
  std::vector<SweepTable> tables;
  for (const int threads : {1, 2, 4}) {
    const std::string out = Path("r" + std::to_string(threads) + ".h5");
    const RunSummary s = RunSweep(spec, Options(out, threads));
    EXPECT_TRUE(s.complete);
    EXPECT_EQ(s.computed, 200u);
    EXPECT_EQ(s.threads, threads);
    tables.push_back(ReadSweepResults(out));
    EXPECT_EQ(tables.back().timing.at("threads"), std::to_string(threads));
    EXPECT_FALSE(fs::exists(JournalPath(out, 0)));
  }
  ASSERT_EQ(tables[0].rows, 200u);
  ExpectSameCases(tables[0], tables[1]);
  ExpectSameCases(tables[0], tables[2]);
  // The table has the parameters beside the outcomes, with units.
  const SweepTable& t = tables[0];
  EXPECT_EQ(t.units.at("spin_rate"), "rad/s");
  EXPECT_EQ(t.units.at("first_flip_time"), "s");
  EXPECT_EQ(t.texts.at("law").size(), 200u);
  EXPECT_EQ(t.run_time.size(), 200u);
  EXPECT_GT(*std::min_element(t.run_time.begin(), t.run_time.end()), 0.0);
  const std::vector<double>& flipped = t.numbers.at("flipped");
  EXPECT_GT(std::count(flipped.begin(), flipped.end(), 1.0), 0);
}

TEST_F(SweepDirTest, HingeSweepIsBitIdenticalForOneAndTwoThreadsAndAfterAResume) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", HingeSweepText(3, 4)));  // 36 cases
  const std::string one = Path("one.h5");
  const std::string two = Path("two.h5");
  ASSERT_TRUE(RunSweep(spec, Options(one, 1)).complete);
  ASSERT_TRUE(RunSweep(spec, Options(two, 2)).complete);
  const SweepTable t = ReadSweepResults(one);
  ExpectSameCases(t, ReadSweepResults(two));
  // Interrupted after 10 cases and resumed: every column through the journal.
  const std::string out = Path("resumed.h5");
  std::atomic<bool> cancel{false};
  std::atomic<int> finished{0};
  RunOptions o = Options(out, 2);
  o.cancel = &cancel;
  o.on_case_done = [&](std::size_t) {
    if (++finished >= 10) cancel = true;
  };
  ASSERT_FALSE(RunSweep(spec, o).complete);
  RunOptions r = Options(out, 2);
  r.resume = true;
  const RunSummary resumed = RunSweep(spec, r);
  ASSERT_TRUE(resumed.complete);
  EXPECT_GE(resumed.resumed, 10u);
  ExpectSameCases(t, ReadSweepResults(out));
  // The hinge columns, with units; the failure modes show in them.
  EXPECT_EQ(t.units.at("max_latch_w_jump"), "rad/s");
  EXPECT_EQ(t.units.at("max_latch_impulse"), "N m s");
  EXPECT_EQ(t.units.at("energy_dissipated_events"), "J");
  EXPECT_EQ(t.units.at("predicted_flip_half_period"), "s");
  EXPECT_EQ(t.units.at("latch_fails[wing_minus_x]"), "none");
  EXPECT_NEAR(std::stod(t.attributes.at("latch_shock_limit")), 15.0 * M_PI / 180.0, 1e-15);
  const std::vector<double>& all = t.numbers.at("all_latched");
  const std::vector<double>& latched = t.numbers.at("latched_count");
  EXPECT_GT(std::count(all.begin(), all.end(), 1.0), 0);
  EXPECT_GT(std::count(all.begin(), all.end(), 0.0), 0);
  for (std::size_t i = 0; i < t.rows; ++i) {
    EXPECT_EQ(all[i] == 1.0, latched[i] == 2.0) << "case " << i;
  }
  EXPECT_EQ(resumed.will_flip,
            static_cast<std::size_t>(std::count(t.numbers.at("will_flip").begin(),
                                                t.numbers.at("will_flip").end(), 1.0)));
}

TEST_F(SweepDirTest, CsvHasOneLinePerCase) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", SweepText(2, 3)));
  RunOptions o = Options(Path("r.h5"), 2);
  o.csv = true;
  ASSERT_TRUE(RunSweep(spec, o).complete);
  std::ifstream f(Path("r.h5.csv"));
  std::string header;
  std::getline(f, header);
  EXPECT_EQ(header.rfind("case_index [1],grid_index [1],sample_index [1],deploy_duration_scale [1],"
                         "spin_rate [rad/s],nutation [rad],",
                         0),
            0u)
      << header;
  EXPECT_NE(header.find(",first_flip_time [s],"), std::string::npos);
  int lines = 0;
  for (std::string line; std::getline(f, line);) ++lines;
  EXPECT_EQ(lines, 12);
}

TEST_F(SweepDirTest, CancelledSweepResumesWithoutRepeatingOrLosingCases) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", SweepText(4, 10)));  // 160 cases
  const std::string reference = Path("reference.h5");
  ASSERT_TRUE(RunSweep(spec, Options(reference, 2)).complete);

  const std::string out = Path("r.h5");
  std::atomic<bool> cancel{false};
  std::atomic<int> finished{0};
  RunOptions o = Options(out, 2);
  o.cancel = &cancel;
  o.on_case_done = [&](std::size_t) {
    if (++finished >= 40) cancel = true;
  };
  const RunSummary first = RunSweep(spec, o);
  EXPECT_FALSE(first.complete);
  EXPECT_FALSE(fs::exists(out));
  const std::vector<std::size_t> journaled = JournalIndices(JournalPath(out, 0), spec);
  EXPECT_EQ(journaled.size(), first.computed);
  EXPECT_GE(journaled.size(), 40u);

  // Without --resume the journal is not overwritten.
  EXPECT_THROW(RunSweep(spec, Options(out, 2)), std::runtime_error);

  // A record torn by a crash at the end of the journal is dropped on resume.
  {
    std::ofstream torn(JournalPath(out, 0), std::ios::app | std::ios::binary);
    torn << "partial record";
  }
  std::mutex mutex;
  std::vector<std::size_t> recomputed;
  RunOptions r = Options(out, 2);
  r.resume = true;
  r.on_case_done = [&](std::size_t i) {
    const std::lock_guard<std::mutex> lock(mutex);
    recomputed.push_back(i);
  };
  const RunSummary second = RunSweep(spec, r);
  EXPECT_TRUE(second.complete);
  EXPECT_EQ(second.resumed, journaled.size());
  EXPECT_EQ(second.computed, 160u - journaled.size());
  std::set<std::size_t> all(journaled.begin(), journaled.end());
  for (std::size_t i : recomputed) EXPECT_TRUE(all.insert(i).second) << "case " << i << " repeated";
  EXPECT_EQ(all.size(), 160u);
  EXPECT_FALSE(fs::exists(JournalPath(out, 0)));
  ExpectSameCases(ReadSweepResults(reference), ReadSweepResults(out));
  const SweepTable t = ReadSweepResults(out);
  EXPECT_EQ(t.timing.at("resumed_cases"), std::to_string(journaled.size()));
}

TEST_F(SweepDirTest, KilledSweepResumesWithoutRepeatingOrLosingCases) {
  // 1200 cases, killed after 150: the child is still far from its end when the kill comes
  // (1050 cases left, about 0.4 s in Release).
  const SweepSpec spec = LoadSweep(Write("s.yaml", SweepText(10, 12)));
  const std::string out = Path("r.h5");
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    // The child: a sweep that reports each finished case (after its journal record).
    ::close(fds[0]);
    RunOptions o = Options(out, 2);
    o.on_case_done = [fd = fds[1]](std::size_t i) {
      const std::uint64_t x = i;
      if (::write(fd, &x, sizeof(x)) != sizeof(x)) ::_exit(4);
    };
    try {
      RunSweep(spec, o);
    } catch (...) {
      ::_exit(3);
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  std::vector<std::size_t> reported;
  std::uint64_t x = 0;
  while (reported.size() < 150 && ::read(fds[0], &x, sizeof(x)) == sizeof(x)) {
    reported.push_back(x);
  }
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  while (::read(fds[0], &x, sizeof(x)) == sizeof(x)) reported.push_back(x);
  ::close(fds[0]);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the sweep ended before it was killed";
  ASSERT_GE(reported.size(), 150u);
  EXPECT_FALSE(fs::exists(out));

  // Loses nothing: every case reported finished is in the journal, once.
  const std::vector<std::size_t> journaled = JournalIndices(JournalPath(out, 0), spec);
  const std::set<std::size_t> in_journal(journaled.begin(), journaled.end());
  EXPECT_EQ(in_journal.size(), journaled.size());
  for (std::size_t i : reported) EXPECT_EQ(in_journal.count(i), 1u) << "case " << i << " lost";

  // Repeats nothing: the resumed run computes exactly the other cases.
  std::mutex mutex;
  std::vector<std::size_t> recomputed;
  RunOptions r = Options(out, 2);
  r.resume = true;
  r.on_case_done = [&](std::size_t i) {
    const std::lock_guard<std::mutex> lock(mutex);
    recomputed.push_back(i);
  };
  const RunSummary s = RunSweep(spec, r);
  ASSERT_TRUE(s.complete);
  EXPECT_EQ(s.resumed, journaled.size());
  std::set<std::size_t> all = in_journal;
  for (std::size_t i : recomputed) EXPECT_TRUE(all.insert(i).second) << "case " << i << " repeated";
  EXPECT_EQ(all.size(), spec.case_count());

  // And the result is the uninterrupted run's.
  const std::string reference = Path("reference.h5");
  ASSERT_TRUE(RunSweep(spec, Options(reference, 2)).complete);
  ExpectSameCases(ReadSweepResults(reference), ReadSweepResults(out));
}

// The destination was found unusable only after every case had run; it is
// checked first (no case runs), and --threads is capped at kMaxThreads.
TEST_F(SweepDirTest, DestinationAndThreadsAreCheckedBeforeAnyCase) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", SweepText(2, 2)));
  std::atomic<int> ran{0};
  auto expect_refused = [&](RunOptions o, const std::string& part) {
    o.on_case_done = [&](std::size_t) { ran.fetch_add(1); };
    try {
      RunSweep(spec, o);
      ADD_FAILURE() << "accepted " << o.output << " with " << o.threads << " threads";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expect_refused(Options(Path("missing/r.h5"), 1), "the output's folder");
  fs::create_directories(Path("folder"));
  expect_refused(Options(Path("folder"), 1), "output is a folder");
  expect_refused(Options(Path("r.h5"), kMaxThreads + 1), "must be in [0, 256]");
  expect_refused(Options(Path("r.h5"), -1), "must be in [0, 256]");
  EXPECT_EQ(ran.load(), 0);
  EXPECT_FALSE(fs::exists(JournalPath(Path("r.h5"), 0)));
  EXPECT_TRUE(fs::is_empty(Path("folder")));
}

TEST_F(SweepDirTest, JournalOfAnotherSweepIsRefused) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", SweepText(2, 3)));
  const std::string out = Path("r.h5");
  std::atomic<bool> cancel{true};  // stops at once: a journal with its header only
  RunOptions o = Options(out, 1);
  o.cancel = &cancel;
  EXPECT_FALSE(RunSweep(spec, o).complete);
  ASSERT_TRUE(fs::exists(JournalPath(out, 0)));
  const SweepSpec other = LoadSweep(Write("s.yaml", SweepText(2, 4)));
  RunOptions r = Options(out, 1);
  r.resume = true;
  try {
    RunSweep(other, r);
    FAIL() << "resumed another sweep's journal";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("belongs to another sweep"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(SweepDirTest, JournalOfAnotherBuildIsRefusedOnResume) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", SweepText(2, 3)));
  const std::string out = Path("r.h5");
  // A journal as another build of deploysim (another version or commit) would leave it,
  // with one finished case in it.
  const std::string other_build = "deploysim 0.0.9 (v0.0.9-3-g0123456789ab; GNU 11.0.0)";
  ASSERT_NE(other_build, kBuildId);
  {
    JournalWriter w(JournalPath(out, 0), Fingerprint(spec), spec.case_count(), other_build);
    w.Append(0, CaseOutcome{});
  }
  RunOptions r = Options(out, 1);
  r.resume = true;
  try {
    RunSweep(spec, r);
    FAIL() << "resumed a journal of another build";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("written by another build (" + other_build + "; this is " + kBuildId),
              std::string::npos)
        << what;
  }
  EXPECT_FALSE(fs::exists(out));
  // The same build resumes its own journal.
  fs::remove(JournalPath(out, 0));
  {
    JournalWriter w(JournalPath(out, 0), Fingerprint(spec), spec.case_count());
    w.Append(0, CaseOutcome{});
  }
  const RunSummary s = RunSweep(spec, r);
  EXPECT_TRUE(s.complete);
  EXPECT_EQ(s.resumed, 1u);
}

TEST_F(SweepDirTest, JournalOfAnOlderFormatIsRefusedOnResume) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", SweepText(2, 3)));
  const std::string out = Path("r.h5");
  // The header of a format-1 journal (before the build identity was recorded).
  Write("r.h5.partial", std::string("DSWPJRN1") + std::string(24, '\0'));
  RunOptions r = Options(out, 1);
  r.resume = true;
  try {
    RunSweep(spec, r);
    FAIL() << "resumed a journal of an older format";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("written by another version of deploysim (journal "
                                         "format 1, this build writes 2)"),
              std::string::npos)
        << e.what();
  }
}

TEST(SweepJournal, BuildIdentityNamesVersionSourcesAndCompiler) {
  const std::string id = kBuildId;
  EXPECT_EQ(id.rfind(std::string("deploysim ") + kVersion + " (", 0), 0u) << id;
  EXPECT_NE(id.find("; "), std::string::npos) << id;  // "<git describe>; <compiler>"
}

// ---- MPI ----

/// Run by mpirun (below) in each rank: the sweep named by DEPLOYSIM_SWEEP_MPI_WORKER
/// ("<sweep file>|<output>"). Skipped in ordinary test runs.
TEST(SweepMpiWorker, Run) {
  const char* job = std::getenv("DEPLOYSIM_SWEEP_MPI_WORKER");
  if (job == nullptr) GTEST_SKIP() << "only run by SweepMpiTest through mpirun";
  const std::string s(job);
  const std::size_t bar = s.find('|');
  MpiSession mpi(nullptr, nullptr);
  ASSERT_TRUE(mpi.active());
  const SweepSpec spec = LoadSweep(s.substr(0, bar));
  RunOptions o = Options(s.substr(bar + 1), 1);
  o.mpi = &mpi;
  const RunSummary summary = RunSweep(spec, o);
  EXPECT_TRUE(summary.complete);
  EXPECT_EQ(summary.ranks, 2);
}

/// Runs `sweep_text` with 2 threads and under mpirun with 2 ranks x 1 thread; the two
/// results tables must be bit-identical.
void ExpectMpiRunMatchesTheThreadedRun(const SweepDirTest& t, const std::string& sweep_text) {
  const std::string sweep = t.Write("s.yaml", sweep_text);
  const SweepSpec spec = LoadSweep(sweep);
  const std::string reference = t.Path("threads.h5");
  ASSERT_TRUE(RunSweep(spec, Options(reference, 2)).complete);

  const std::string out = t.Path("mpi.h5");
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  ASSERT_EQ(::setenv("DEPLOYSIM_SWEEP_MPI_WORKER", (sweep + "|" + out).c_str(), 1), 0);
  // As root mpirun needs --allow-run-as-root; TCP on the loopback interface. mpirun exits
  // with 0 even when it refuses to run, so the output file is what counts.
  const std::string cmd = "'" + MpiExecutable() +
                          "' --allow-run-as-root --oversubscribe -np 2 --mca btl self,tcp "
                          "--mca btl_tcp_if_include lo --mca oob_tcp_if_include lo "
                          "-x DEPLOYSIM_SWEEP_MPI_WORKER '" +
                          self + "' --gtest_filter=SweepMpiWorker.Run > '" + t.Path("mpi.log") +
                          "' 2>&1";
  const int status = std::system(cmd.c_str());
  ::unsetenv("DEPLOYSIM_SWEEP_MPI_WORKER");
  std::ifstream log(t.Path("mpi.log"));
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  // Not the exit status: mpirun reports 0 when it refuses to run, and a rank's exit code
  // may reflect the MPI library (e.g. leak reports under sanitizers) rather than the sweep.
  ASSERT_TRUE(fs::exists(out)) << "mpirun (status " << status << ") wrote no results:\n" << text;
  const SweepTable table = ReadSweepResults(out);
  EXPECT_EQ(table.timing.at("ranks"), "2");
  ExpectSameCases(ReadSweepResults(reference), table);
  EXPECT_FALSE(fs::exists(JournalPath(out, 0)));
  EXPECT_FALSE(fs::exists(JournalPath(out, 1)));
}

TEST_F(SweepDirTest, MpiRunWithTwoRanksMatchesTheThreadedRun) {
  if (!MpiBuilt()) GTEST_SKIP() << "built without MPI (cmake -DDEPLOYSIM_WITH_MPI=ON)";
  ExpectMpiRunMatchesTheThreadedRun(*this, SweepText(4, 5));  // 80 cases
}

TEST_F(SweepDirTest, MpiRunOfAHingeSweepMatchesTheThreadedRun) {
  if (!MpiBuilt()) GTEST_SKIP() << "built without MPI (cmake -DDEPLOYSIM_WITH_MPI=ON)";
  ExpectMpiRunMatchesTheThreadedRun(*this, HingeSweepText(2, 5));  // 20 cases
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::sweep
