#include "deploysim/sweep/runner.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <vector>

#include "deploysim/sweep/journal.h"
#include "deploysim/sweep/outcome.h"
#include "deploysim/sweep/parallel.h"
#include "deploysim/sweep/progress.h"

namespace deploysim::sweep {

namespace {

namespace fs = std::filesystem;

constexpr double kSyncInterval = 0.5;   // [s] between fsyncs of the journal
constexpr double kPollInterval = 0.05;  // [s] main-thread wake-ups (progress, cancel)

/// Every journal of `output` on disk: `<output>.partial` and `<output>.partial.<r>`.
std::vector<std::string> ExistingJournals(const std::string& output) {
  const fs::path out(output);
  const fs::path dir = out.parent_path().empty() ? fs::path(".") : out.parent_path();
  const std::string stem = out.filename().string() + ".partial";
  std::vector<std::string> found;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name == stem ||
        (name.size() > stem.size() + 1 && name.compare(0, stem.size() + 1, stem + ".") == 0 &&
         name.find_first_not_of("0123456789", stem.size() + 1) == std::string::npos)) {
      found.push_back((out.parent_path() / name).string());
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

/// The output's destination, before any case runs: not a folder, in an existing folder
/// that this process may write. Throws std::invalid_argument (a folder) or
/// std::runtime_error (the folder is missing or not writable), one line.
void CheckDestination(const std::string& output) {
  std::error_code ec;
  const fs::path out(output);
  if (fs::is_directory(out, ec) || (!output.empty() && output.back() == '/')) {
    throw std::invalid_argument(output + ": output is a folder (rule: -o names a file)");
  }
  const fs::path dir = out.parent_path().empty() ? fs::path(".") : out.parent_path();
  if (!fs::is_directory(dir, ec)) {
    throw std::runtime_error(output + ": the output's folder " + dir.string() +
                             " does not exist or is not a folder (rule: write into an existing "
                             "folder)");
  }
  if (::access(dir.c_str(), W_OK | X_OK) != 0) {
    throw std::runtime_error(output + ": the output's folder " + dir.string() +
                             " is not writable: " + std::strerror(errno));
  }
}

/// SimulateOutcome; an error that does not name the sweep file (e.g. one from a root
/// solver deep inside) is rethrown as "<sweep file>: case <i>: <message>", same type class
/// (std::invalid_argument or std::runtime_error).
CaseOutcome OutcomeNamingFile(const SweepSpec& spec, const Case& c) {
  const std::string where = (spec.source.empty() ? std::string("sweep") : spec.source) + ": case " +
                            std::to_string(c.parameters.index) + ": ";
  try {
    return SimulateOutcome(c, spec.outcome);
  } catch (const std::invalid_argument& e) {
    if (std::string(e.what()).rfind(spec.source, 0) == 0 && !spec.source.empty()) throw;
    throw std::invalid_argument(where + e.what());
  } catch (const std::exception& e) {
    if (std::string(e.what()).rfind(spec.source, 0) == 0 && !spec.source.empty()) throw;
    throw std::runtime_error(where + e.what());
  }
}

int DefaultThreads(const MpiSession* mpi) {
  const int local = mpi != nullptr ? std::max(1, mpi->local_size()) : 1;
  return std::max(1, HardwareThreads() / local);
}

}  // namespace

CaseOutcome SimulateCase(const SweepSpec& spec, std::size_t i) {
  return OutcomeNamingFile(spec, BuildCase(spec, i));
}

std::string JournalPath(const std::string& output, int rank) {
  return output + ".partial" + (rank == 0 ? std::string() : "." + std::to_string(rank));
}

namespace {

/// Seconds of steady-clock time since `t0`.
double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The options a run needs before anything else: an output file, a thread count in
/// range, a destination that can be written.
void CheckRunOptions(const RunOptions& options) {
  if (options.output.empty()) throw std::invalid_argument("sweep: no output file given");
  if (options.threads < 0 || options.threads > kMaxThreads) {
    throw std::invalid_argument("sweep: threads = " + std::to_string(options.threads) +
                                ": must be in [0, " + std::to_string(kMaxThreads) +
                                "] (0: all hardware threads)");
  }
  CheckDestination(options.output);
}

/// The summary's fixed part: case count, rank layout, threads and this process's journal.
RunSummary StartSummary(const SweepSpec& spec, const RunOptions& options) {
  RunSummary summary;
  summary.cases = spec.case_count();
  summary.rank = options.mpi != nullptr ? options.mpi->rank() : 0;
  summary.ranks = options.mpi != nullptr ? options.mpi->size() : 1;
  summary.threads = options.threads > 0 ? options.threads : DefaultThreads(options.mpi);
  summary.journal = JournalPath(options.output, summary.rank);
  return summary;
}

/// Every journal of the output (any rank's, from any earlier run); they are in the way
/// unless the run resumes.
std::vector<std::string> JournalsToResume(const RunOptions& options) {
  std::vector<std::string> journals = ExistingJournals(options.output);
  if (!journals.empty() && !options.resume) {
    throw std::runtime_error(journals.front() +
                             ": an unfinished sweep's journal is in the way: pass --resume to "
                             "finish that sweep, or delete the journal to start afresh");
  }
  return journals;
}

/// Loads the records of `journals` into `outcomes` (the first record of a case wins)
/// and marks them `done`; returns how many cases they held.
std::size_t LoadJournals(const std::vector<std::string>& journals,
                         std::uint64_t fingerprint,
                         std::vector<CaseOutcome>& outcomes,
                         std::vector<char>& done) {
  const std::size_t n = outcomes.size();
  std::size_t resumed = 0;
  for (const std::string& j : journals) {
    for (const auto& [index, outcome] : ReadJournal(j, fingerprint, n).records) {
      if (done[index]) continue;
      done[index] = 1;
      outcomes[index] = outcome;
      ++resumed;
    }
  }
  return resumed;
}

/// This process's share: every ranks-th case from its rank on, less those already done.
std::vector<std::size_t> ShareOf(const RunSummary& summary, const std::vector<char>& done) {
  std::vector<std::size_t> todo;
  for (std::size_t i = static_cast<std::size_t>(summary.rank); i < done.size();
       i += static_cast<std::size_t>(summary.ranks)) {
    if (!done[i]) todo.push_back(i);
  }
  return todo;
}

/// Runs the cases `todo` on the worker threads, each journalled as it finishes; the
/// calling thread shows progress and syncs the journal meanwhile. Sets the summary's
/// computed count and parallel time.
void RunCases(const SweepSpec& spec,
              const RunOptions& options,
              const std::vector<std::size_t>& todo,
              std::uint64_t fingerprint,
              std::optional<ProgressReporter>& progress,
              std::vector<CaseOutcome>& outcomes,
              RunSummary& summary) {
  JournalWriter journal(summary.journal, fingerprint, outcomes.size());
  std::atomic<std::size_t> finished{0};
  ParallelOptions parallel;
  parallel.threads = summary.threads;
  if (options.cancel != nullptr) {
    parallel.cancelled = [&options] { return options.cancel->load(); };
  }
  // The calling thread: progress and periodic fsync while the workers run.
  auto last_sync = std::chrono::steady_clock::now();
  parallel.monitor_interval = kPollInterval;
  parallel.monitor = [&] {
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_sync).count() >= kSyncInterval) {
      journal.Sync();
      last_sync = now;
    }
    // Rank 0 sees its own share only: scaled to the whole sweep for the display.
    if (progress) {
      progress->Update(summary.resumed + finished.load() * static_cast<std::size_t>(summary.ranks));
    }
  };
  const auto parallel0 = std::chrono::steady_clock::now();
  // A worker's exception is rethrown after the others have stopped (ParallelFor); the
  // journal keeps every case finished before it.
  try {
    ParallelFor(
        todo.size(),
        [&](std::size_t k) {
          const std::size_t i = todo[k];
          const CaseOutcome o = SimulateCase(spec, i);
          journal.Append(i, o);
          outcomes[i] = o;  // slot i is this worker's alone
          finished.fetch_add(1);
          if (options.on_case_done) options.on_case_done(i);
        },
        parallel);
  } catch (const ThreadStartError& e) {
    // The workers that started have stopped; their cases are in the journal.
    journal.Sync();
    throw std::runtime_error(options.output + ": " + e.what() + "; the journal " + summary.journal +
                             " keeps " + std::to_string(finished.load()) +
                             " finished cases: rerun with fewer --threads and --resume");
  }
  summary.parallel_seconds = SecondsSince(parallel0);
  journal.Sync();
  summary.computed = finished.load();
}

/// With several ranks: rank 0 collects the outcomes computed on the other ranks.
void GatherOutcomes(const MpiSession* mpi,
                    bool root,
                    const std::vector<std::size_t>& todo,
                    std::vector<CaseOutcome>& outcomes,
                    std::vector<char>& done) {
  if (mpi == nullptr || mpi->size() <= 1) return;
  std::vector<CaseRecord> mine;
  mine.reserve(todo.size());
  for (const std::size_t i : todo) mine.emplace_back(i, outcomes[i]);
  const std::vector<char> all = mpi->GatherToRoot(EncodeRecords(mine));
  if (!root) return;
  for (const CaseRecord& r : DecodeRecords(all)) {
    if (r.first >= outcomes.size()) {
      throw std::runtime_error("sweep: a rank sent an unknown case index");
    }
    if (!done[r.first]) {
      done[r.first] = 1;
      outcomes[r.first] = r.second;
    }
  }
}

/// The summary's counts over all cases; every case must have its result.
void CountOutcomes(const std::vector<CaseOutcome>& outcomes,
                   const std::vector<char>& done,
                   RunSummary& summary) {
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    if (!done[i]) {
      throw std::runtime_error("sweep: case " + std::to_string(i) +
                               " has no result after the run (internal error)");
    }
    summary.flipped += outcomes[i].flip_count > 0 ? 1 : 0;
    summary.tumbling += outcomes[i].final_class == MotionClass::kTumbling ? 1 : 0;
    summary.will_flip += WillFlip(outcomes[i]) ? 1 : 0;
    summary.failed += outcomes[i].final_class == MotionClass::kFailed ? 1 : 0;
  }
  // By outcome, in the classes' order (most severe first; a flat spin before the other
  // transitions).
  std::map<std::pair<std::int32_t, std::string>, std::size_t> by;
  for (const CaseOutcome& o : outcomes) {
    const std::string name = OutcomeName(o);
    ++by[{2 * o.outcome_class + (name == "flat spin" ? 0 : 1), name}];
  }
  for (const auto& [key, count] : by) summary.outcomes.emplace_back(key.second, count);
}

/// Writes the results file (and CSV), then removes the journals they replace.
void WriteResults(const SweepSpec& spec,
                  const RunOptions& options,
                  const std::vector<CaseOutcome>& outcomes,
                  const RunSummary& summary) {
  RunInfo info;
  info.threads = summary.threads;
  info.ranks = summary.ranks;
  info.wall_seconds = summary.wall_seconds;
  info.resumed_cases = summary.resumed;
  info.computed_cases = outcomes.size() - summary.resumed;
  WriteSweepOutputs(options.output, options.csv ? options.output + ".csv" : "", spec, outcomes,
                    info);
  // Only now that the results are safe: the journals go.
  for (const std::string& j : ExistingJournals(options.output)) fs::remove(j);
}

}  // namespace

RunSummary RunSweep(const SweepSpec& spec, const RunOptions& options) {
  const auto wall0 = std::chrono::steady_clock::now();
  CheckRunOptions(options);
  RunSummary summary = StartSummary(spec, options);
  const bool root = summary.rank == 0;
  const std::uint64_t fingerprint = Fingerprint(spec);
  const std::size_t n = summary.cases;

  // Resume: load every journal (any rank's, from any earlier run).
  const std::vector<std::string> journals = JournalsToResume(options);
  std::vector<CaseOutcome> outcomes(n);
  std::vector<char> done(n, 0);
  summary.resumed = LoadJournals(journals, fingerprint, outcomes, done);

  const std::vector<std::size_t> todo = ShareOf(summary, done);

  // Every rank has listed the journals before any rank creates its own.
  if (options.mpi != nullptr) options.mpi->Barrier();

  std::optional<ProgressReporter> progress;
  if (options.progress != nullptr && root) {
    progress.emplace(*options.progress, options.progress_tty, n, summary.resumed,
                     options.progress_interval,
                     summary.ranks > 1 ? "sweep (rank 0 of " + std::to_string(summary.ranks) + ")"
                                       : std::string("sweep"));
  }
  RunCases(spec, options, todo, fingerprint, progress, outcomes, summary);

  const bool complete_here = summary.computed == todo.size();
  const bool complete =
      options.mpi != nullptr ? options.mpi->AllTrue(complete_here) : complete_here;
  const std::size_t computed_everywhere =
      options.mpi != nullptr ? static_cast<std::size_t>(options.mpi->Sum(summary.computed))
                             : summary.computed;
  if (!complete) {
    summary.finished = summary.resumed + computed_everywhere;
    if (progress) progress->Finish(summary.finished, false);
    summary.wall_seconds = SecondsSince(wall0);
    return summary;
  }
  for (const std::size_t i : todo) done[i] = 1;
  GatherOutcomes(options.mpi, root, todo, outcomes, done);
  if (progress) progress->Finish(n, true);

  summary.complete = true;
  summary.wall_seconds = SecondsSince(wall0);
  if (root) {
    CountOutcomes(outcomes, done, summary);
    WriteResults(spec, options, outcomes, summary);
  }
  summary.finished = n;
  if (options.mpi != nullptr) options.mpi->Barrier();
  return summary;
}

std::string FormatSummary(const RunSummary& s, const RunOptions& options) {
  if (!s.complete) {
    return std::to_string(s.finished) + " of " + std::to_string(s.cases) +
           " cases finished (journal " + s.journal +
           "); run the same command with --resume to finish the sweep";
  }
  std::string outcomes;
  for (const auto& [name, count] : s.outcomes) {
    outcomes += (outcomes.empty() ? "; outcomes: " : ", ") + std::to_string(count) + " " + name;
  }
  return std::to_string(s.cases) + " cases: " + std::to_string(s.flipped) + " flipped (" +
         std::to_string(s.will_flip) + " will flip), " + std::to_string(s.tumbling) +
         " tumbling at the end, " + std::to_string(s.failed) + " failed" + outcomes + "; wrote " +
         options.output + (options.csv ? " and " + options.output + ".csv" : "");
}

}  // namespace deploysim::sweep
