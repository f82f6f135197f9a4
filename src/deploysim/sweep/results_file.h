#pragma once

/// Sweep results (docs/sweeps.md "Results file"): an HDF5 table, one row per case,
/// the parameters beside the outcomes, and optionally the same table as CSV. Both are
/// written atomically (io::AtomicFile): a reader sees the complete file or none.
///
/// HDF5 layout (schema_version 1): the group /cases holds one 1-D dataset per column, all
/// of length N (the case count), in the order of the root attribute `columns`; numbers
/// are IEEE little-endian doubles or 64-bit integers, text variable-length UTF-8 strings;
/// every dataset has the string attributes `units`, `description` and `role` (`index`,
/// `parameter` or `outcome`). Everything under /cases is a deterministic function of the
/// sweep (bit-identical whatever the thread count, rank count or interruptions). Run
/// times and how the sweep was run (threads, ranks, resumed cases) are kept apart in
/// /timing, as they differ from run to run.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "deploysim/sweep/outcome.h"
#include "deploysim/sweep/sweep_spec.h"

namespace deploysim::sweep {

/// Version of the results layout (root attribute `schema_version`).
inline constexpr int kResultsSchemaVersion = 1;

/// How a sweep was run (stored in /timing; not part of the deterministic results).
struct RunInfo {
  int threads = 1;                 ///< Worker threads per process.
  int ranks = 1;                   ///< MPI ranks (1 without MPI).
  double wall_seconds = 0.0;       ///< Wall time of this run (the resumed part only).
  std::size_t resumed_cases = 0;   ///< Cases read from the journal.
  std::size_t computed_cases = 0;  ///< Cases computed by this run.
};

/// Writes the table of `outcomes` (outcomes[i] is case i; outcomes.size() == case count).
/// Throws std::invalid_argument on a size mismatch, std::runtime_error naming `path` on
/// I/O errors (nothing is left at `path` then; an older file there is kept).
void WriteSweepResults(const std::string& path,
                       const SweepSpec& spec,
                       const std::vector<CaseOutcome>& outcomes,
                       const RunInfo& info);

/// The same table as CSV: a header of `name [units]`, one line per case, numbers in the
/// shortest form that reads back exactly (`nan` for none), `run_time [s]` last.
void WriteSweepCsv(const std::string& path,
                   const SweepSpec& spec,
                   const std::vector<CaseOutcome>& outcomes);

/// The outputs of a finished sweep: the results file and, if `csv_path` is not empty,
/// its CSV. Both temporaries are written completely and flushed before either replaces
/// anything: a failure until then (disk full, size limit, signal) leaves both targets as
/// they were and no temporary; only a failure of the CSV's rename, after the results
/// file's, can leave the new results beside an old CSV.
void WriteSweepOutputs(const std::string& path,
                       const std::string& csv_path,
                       const SweepSpec& spec,
                       const std::vector<CaseOutcome>& outcomes,
                       const RunInfo& info);

/// One column of the /cases table, in memory: what WriteSweepResults writes (and the
/// Python package returns as numpy arrays).
struct ResultColumn {
  enum class Type { kDouble, kInt, kText };
  std::string name;
  std::string units;
  std::string description;
  std::string role;  ///< index | parameter | outcome | timing
  Type type = Type::kDouble;
  std::vector<double> d;        ///< kDouble
  std::vector<std::int64_t> i;  ///< kInt
  std::vector<std::string> s;   ///< kText
};

/// The /cases columns of `outcomes` (outcomes[i] is case i), in file order: the indices,
/// the parameters, then the outcome columns of CaseOutcomeTable (case_outcome_table.h).
/// Throws std::invalid_argument on a size mismatch.
std::vector<ResultColumn> ResultColumns(const SweepSpec& spec,
                                        const std::vector<CaseOutcome>& outcomes);

/// The /timing columns of `outcomes` (role `timing`: CaseOutcomeTable's fields that vary
/// from run to run, run_time): the datasets /timing/<name>, the CSV's last columns.
std::vector<ResultColumn> TimingColumns(const SweepSpec& spec,
                                        const std::vector<CaseOutcome>& outcomes);

/// A results file as read back (for tests, tools and comparisons).
struct SweepTable {
  std::vector<std::string> columns;                       ///< /cases columns, in order.
  std::map<std::string, std::vector<double>> numbers;     ///< Numeric columns (ints exact).
  std::map<std::string, std::vector<std::string>> texts;  ///< Text columns.
  std::map<std::string, std::string> units;               ///< By column name.
  std::map<std::string, std::string> attributes;          ///< Root attributes.
  std::vector<double> run_time;                           ///< /timing/run_time [s].
  std::map<std::string, std::string> timing;              ///< /timing attributes.
  std::size_t rows = 0;
};

/// Reads a file written by WriteSweepResults. Throws std::runtime_error naming `path`.
SweepTable ReadSweepResults(const std::string& path);

}  // namespace deploysim::sweep
