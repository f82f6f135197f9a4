#pragma once

/// Running a sweep (docs/sweeps.md): all cases on a pool of std::threads (and, in an MPI
/// run, sharded over the ranks: rank r of N takes the cases i with i % N == r), each
/// finished case appended to the journal at once, the final results written atomically
/// by rank 0 and the journal removed.
///
/// Determinism: a case's outcome is a pure function of (spec, case index) (BuildCase,
/// SimulateOutcome; Monte Carlo draws from Rng(seed, sample, parameter)); workers share
/// nothing mutable but the case counter and the journal, and each outcome lands in its
/// own slot. The /cases table is therefore bit-identical whatever the thread count, rank
/// count, scheduling order or interruptions; only /timing differs.
///
/// Journal: `<output>.partial` (rank r > 0 of an MPI run: `<output>.partial.<r>`). An
/// existing journal means an unfinished sweep: without `resume` the run refuses to start
/// (so that it never silently mixes or discards results); with `resume` the cases in all
/// journals are loaded, never recomputed, and only the rest are run.

#include <atomic>
#include <cstddef>
#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "deploysim/sweep/mpi_session.h"
#include "deploysim/sweep/outcome.h"
#include "deploysim/sweep/results_file.h"
#include "deploysim/sweep/sweep_spec.h"

namespace deploysim::sweep {

struct RunOptions {
  std::string output;   ///< Results file (HDF5). Required.
  bool csv = false;     ///< Also write `<output>.csv`.
  bool resume = false;  ///< Continue from the journal(s).
  /// Worker threads per process; 0: the hardware threads divided by the ranks on this node.
  int threads = 0;
  std::ostream* progress = nullptr;  ///< Progress and notes (stderr); nullptr: quiet.
  bool progress_tty = false;         ///< Bar with rate and ETA (a terminal) vs plain lines.
  double progress_interval = 10.0;   ///< [s] between plain progress lines.
  /// Set to stop: the workers finish their current case and the run returns with
  /// complete = false, the journal flushed (e.g. InstallInterruptHandlers()).
  const std::atomic<bool>* cancel = nullptr;
  /// Called from the worker threads after case i's journal record is written (tests).
  std::function<void(std::size_t)> on_case_done;
  const MpiSession* mpi = nullptr;  ///< MPI session (nullptr: this process alone).
};

struct RunSummary {
  bool complete = false;     ///< The results file was written (rank 0) / the sweep ended.
  std::size_t cases = 0;     ///< Case count of the sweep.
  std::size_t resumed = 0;   ///< Read from journals (all ranks).
  std::size_t computed = 0;  ///< Computed by this process.
  std::size_t finished = 0;  ///< Cases finished so far, over all ranks.
  int threads = 1;
  int ranks = 1;
  int rank = 0;
  double wall_seconds = 0.0;      ///< Whole run (loading journals ... writing results).
  double parallel_seconds = 0.0;  ///< The worker phase alone (the rest is serial).
  std::string journal;            ///< This process's journal path.
  // Rank 0 of a complete sweep: counts over all cases.
  std::size_t flipped = 0;    ///< Cases with at least one flip.
  std::size_t tumbling = 0;   ///< Cases whose final class is tumbling.
  std::size_t will_flip = 0;  ///< Cases whose final motion flips (whatever the horizon).
  std::size_t failed = 0;     ///< Cases whose integration did not reach the end.
  /// Cases per outcome measured from the motion (OutcomeName), most severe first.
  std::vector<std::pair<std::string, std::size_t>> outcomes;
};

/// Journal path of `rank` for results file `output`.
std::string JournalPath(const std::string& output, int rank);

/// Runs the sweep. Before any case: throws std::invalid_argument for threads outside
/// [0, kMaxThreads] (parallel.h) or an output that is a folder, std::runtime_error when
/// the output's folder is missing or not writable. Throws std::runtime_error for I/O
/// problems and when a journal exists without `resume` or belongs to another sweep, and
/// "<output>: cannot start worker thread i of n: <reason>; the journal ... keeps k
/// finished cases: rerun with fewer --threads and --resume" when a thread cannot be
/// created. Rethrows a worker's exception after the other workers have stopped (the
/// journal keeps every finished case), as "<sweep file>: case <i>: <message>" when the
/// message did not name the sweep file.
RunSummary RunSweep(const SweepSpec& spec, const RunOptions& options);

/// Case i of the sweep on the outcome path (BuildCase, SimulateOutcome), as RunSweep runs
/// it: an error that does not name the sweep file is rethrown as "<sweep file>: case <i>:
/// <message>" (std::invalid_argument or std::runtime_error). Thread-safe.
CaseOutcome SimulateCase(const SweepSpec& spec, std::size_t i);

/// One line for the user: "N cases: F flipped (W will flip), T tumbling at the end, X
/// failed; outcomes: A flat spin, B growing, ...; wrote PATH".
std::string FormatSummary(const RunSummary& s, const RunOptions& options);

}  // namespace deploysim::sweep
