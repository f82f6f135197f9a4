#pragma once

/// All-or-nothing file output: write to a temporary file in the target's directory,
/// then rename it onto the target (POSIX rename within one file system is atomic).
/// Readers see either the old file or the complete new one, never a partial one, and a
/// failed write leaves nothing behind.

#include <string>

namespace deploysim::io {

/// A temporary file "<dir>/.<name>.<pid>.<n>.tmp" next to `target`.
/// Invariant: until Commit() succeeds, the temporary is removed when this object is
/// destroyed (including during stack unwinding), and `target` is untouched.
class AtomicFile {
 public:
  /// Creates the empty temporary (mode 0666 & ~umask). Throws std::runtime_error
  /// "<target>: cannot create a temporary file in <dir>: <reason>".
  explicit AtomicFile(std::string target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& target() const { return target_; }
  /// Where to write the contents (close every handle on it before Commit()).
  const std::string& temporary_path() const { return temporary_; }

  /// Flushes the temporary to disk (fsync) and renames it onto the target. Throws
  /// std::runtime_error "<target>: ..." on failure (the temporary is then removed by the
  /// destructor).
  void Commit();

 private:
  std::string target_;
  std::string temporary_;
  bool committed_ = false;
};

}  // namespace deploysim::io
