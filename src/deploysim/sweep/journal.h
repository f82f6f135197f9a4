#pragma once

/// The checkpoint journal of a sweep: every finished case is appended as one fixed-size,
/// checksummed record, so that an interrupted sweep (SIGINT, or the process killed
/// outright) resumes without recomputing or losing a finished case.
///
/// Durability: each record goes to the kernel with one write(2) as soon as its case is
/// finished, so it survives the death of the process (kill -9); the file is fsync'd
/// periodically (Sync) and on close, so at most the last moments are lost when the whole
/// machine goes down. A record torn by a crash (short, or a bad checksum) ends the valid
/// part of the file: readers stop there and the writer truncates it away before appending.
///
/// Layout (native byte order; the journal is a scratch file of one machine):
///   header  "DSWPJRN2" | u64 fingerprint | u64 case count | u32 record size |
///           u32 length L | L bytes: the build identity (kBuildId) | u64 FNV-1a of the header
///   records u64 case index | payload | u64 FNV-1a of both
/// The payload is the case outcome's stored fields in their record order, as
/// CaseOutcomeTable describes them (case_outcome_table.h: slot, bytes).
/// A journal belongs to one sweep definition run by one build of deploysim: its
/// fingerprint (Fingerprint()) covers the sweep file, the base profile and model files
/// and the result layout, and the build identity (version, git describe of the sources,
/// compiler; deploysim/version.h) is stored beside it. Opening a journal with another
/// fingerprint or written by another build is an error: a resumed sweep never mixes the
/// results of two definitions or of two builds.

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "deploysim/sweep/outcome.h"
#include "deploysim/sweep/sweep_spec.h"
#include "deploysim/version.h"

namespace deploysim::sweep {

/// FNV-1a (64-bit) of the texts that define the sweep's results, of the journal and
/// results layout versions and of the build identity kBuildId.
std::uint64_t Fingerprint(const SweepSpec& spec);

/// What a journal file holds (ReadJournal).
struct JournalContents {
  std::vector<std::pair<std::size_t, CaseOutcome>> records;  ///< In file order.
  std::size_t valid_bytes = 0;  ///< Length of the valid part (header + whole records).
  bool torn_tail = false;       ///< Bytes after the valid part (a record torn by a crash).
};

/// Reads `path`. Throws std::runtime_error "<path>: ..." when it cannot be read, is not a
/// sweep journal, was written by another build than `build_id` ("... was written by
/// <its build>; this is <build_id> ..."), or belongs to another sweep (fingerprint or
/// case count differ).
JournalContents ReadJournal(const std::string& path,
                            std::uint64_t fingerprint,
                            std::size_t case_count,
                            const std::string& build_id = kBuildId);

/// Appends records to a journal; thread-safe.
class JournalWriter {
 public:
  /// Opens `path` for appending, creating it with its header if missing; an existing
  /// journal must match (ReadJournal's rules) and a torn tail is truncated away.
  /// `build_id` is the identity recorded in a new journal (tests pass another one).
  JournalWriter(std::string path,
                std::uint64_t fingerprint,
                std::size_t case_count,
                const std::string& build_id = kBuildId);
  ~JournalWriter();
  JournalWriter(const JournalWriter&) = delete;
  JournalWriter& operator=(const JournalWriter&) = delete;

  /// Writes one record with a single write(2). Throws std::runtime_error on I/O errors.
  void Append(std::size_t index, const CaseOutcome& outcome);
  /// fsync(2): makes the records written so far durable.
  void Sync();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::mutex mutex_;
};

/// Size in bytes of one journal record.
std::size_t JournalRecordSize();

/// Finished cases as journal records (to send between MPI ranks), and back. Decoding
/// throws std::runtime_error on a corrupt block.
using CaseRecord = std::pair<std::size_t, CaseOutcome>;
std::vector<char> EncodeRecords(const std::vector<CaseRecord>& records);
std::vector<CaseRecord> DecodeRecords(const std::vector<char>& bytes);

}  // namespace deploysim::sweep
