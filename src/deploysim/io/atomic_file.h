#pragma once

/// All-or-nothing file output: write to a temporary file in the target's directory,
/// then rename it onto the target (POSIX rename within one file system is atomic).
/// Readers see either the old file or the complete new one, never a partial one, and a
/// failed write leaves nothing behind.
///
/// The temporary is anonymous where the file system allows it (Linux O_TMPFILE): it has
/// no name until Commit() links it in, so even SIGKILL or a power cut while writing
/// leaves nothing in the folder. Elsewhere (no O_TMPFILE, no /proc) it is a named file
/// "<dir>/.<name>.<pid>.<n>.tmp"; Commit() uses such a name for the instant between
/// linking and renaming. Named temporaries of dead processes for the same target are
/// removed by the next AtomicFile of that target (RemoveStaleTemporaries), and
/// RemoveTemporariesOnSignals() makes SIGINT/SIGTERM/SIGHUP remove the live ones.

#include <csignal>
#include <cstdint>
#include <string>

namespace deploysim::io {

/// A temporary file next to `target`.
/// Invariant: until Commit() succeeds, the temporary is removed when this object is
/// destroyed (including during stack unwinding), and `target` is untouched.
class AtomicFile {
 public:
  /// Creates the empty temporary (mode 0666 & ~umask), after removing stale temporaries
  /// of `target`. Throws std::runtime_error
  /// "<target>: cannot create a temporary file in <dir>: <reason>".
  /// `allow_anonymous` false: always a named temporary (for writers that must open the
  /// temporary by a real path: HDF5, see atomic_file.cc).
  explicit AtomicFile(std::string target, bool allow_anonymous = true);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& target() const { return target_; }
  /// Where to open the temporary to write its contents ("/proc/self/fd/<n>" for an
  /// anonymous one); close every handle on it before Commit().
  const std::string& temporary_path() const { return temporary_; }
  /// True if the temporary has no name in the folder (O_TMPFILE).
  bool anonymous() const { return anonymous_; }

  /// Makes sure the temporary can grow to `size` bytes: fails now, with a clear message,
  /// rather than in the middle of a library's write. Checks the file size limit
  /// (RLIMIT_FSIZE) and allocates the disk blocks (fallocate, FALLOC_FL_KEEP_SIZE; where
  /// the file system cannot, only the limit is checked). Throws std::runtime_error
  /// "<target>: cannot write: <reason> (no room for <size> bytes)".
  void Reserve(std::uint64_t size);
  /// Gives back blocks reserved beyond the end of the file (after the contents are
  /// complete).
  void ReleaseReserve();

  /// Flushes the temporary to disk (fsync) and renames it onto the target. Throws
  /// std::runtime_error "<target>: ..." on failure (the temporary is then removed by the
  /// destructor).
  void Commit();

 private:
  std::string target_;
  std::string temporary_;  // path to write through
  std::string named_;      // the temporary's name in the folder, if it has one
  int fd_ = -1;            // open on the temporary until destruction
  int slot_ = -1;          // signal-handler registration of named_
  bool anonymous_ = false;
  bool committed_ = false;
  std::uint64_t reserved_ = 0;
};

/// The name of the temporaries of `target` without the "<pid>.<n>.tmp" tail:
/// ".<file name>." where it fits, else a prefix of the name and a hash of it, so that the
/// whole temporary name stays within NAME_MAX (255 bytes) for any valid target name.
std::string TemporaryStem(const std::string& file_name);

/// Removes the named temporaries of `target` ("<dir>/<stem><pid>.<n>.tmp") whose
/// process no longer runs (left by a kill -9 or a crash). Returns how many it removed.
/// Never throws.
int RemoveStaleTemporaries(const std::string& target);

/// Holds SIGINT, SIGTERM and SIGHUP back in the calling thread while it lives (a signal
/// that arrives meanwhile is delivered when it ends). For commits of several files that
/// belong together (an HDF5 file and its CSV): a signal between two renames would leave
/// a new file beside an old one.
class SignalsHeld {
 public:
  SignalsHeld();
  ~SignalsHeld();
  SignalsHeld(const SignalsHeld&) = delete;
  SignalsHeld& operator=(const SignalsHeld&) = delete;

 private:
  sigset_t saved_;  // the thread's mask before
};

/// Installs handlers for SIGINT, SIGTERM and SIGHUP that unlink the live named
/// temporaries of this process (async-signal-safe: unlink of preformatted paths), then
/// end the process by the same signal (a shell reports 128 + signal: 130, 143, 129).
void RemoveTemporariesOnSignals();

}  // namespace deploysim::io
