#pragma once

/// A new HDF5 file, written atomically (AtomicFile), without HDF5 types in the
/// interface: the one place that knows how deploysim lays out HDF5 (datasets of
/// IEEE little-endian doubles with `units` and `description` attributes, variable-length
/// UTF-8 strings, string attributes). Every writer of HDF5 files (trajectories, sweep
/// results, cross-checks) goes through it, so only io includes HDF5.
///
/// Failures: every HDF5 call is checked and reported as std::runtime_error
/// "<path>: <what failed>: <reason>" (the innermost message of HDF5's error stack, or
/// the system's reason). Disk space is reserved before each write (AtomicFile::Reserve),
/// so a full disk or a file size limit is reported before HDF5 writes anything it could
/// not finish; HDF5 itself can then always close the file (HDF5 1.10 crashes at exit
/// if a file it failed to close is left open). After any failure the writer only
/// closes its handles (datasets, groups, then the file) and the temporary goes.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace deploysim::io {

class Hdf5Writer {
 public:
  /// Starts the file (a temporary next to `path`). Throws std::runtime_error naming
  /// `path` on failure.
  explicit Hdf5Writer(const std::string& path);
  /// Without Commit() nothing is left at `path` and the temporary is removed.
  ~Hdf5Writer();
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;

  /// A dataset of doubles at `dataset` ("/time", "/events/flip_time": groups are made as
  /// needed), row-major with shape `dims`; data.size() must be the product of dims.
  void Doubles(const std::string& dataset,
               const std::vector<std::size_t>& dims,
               const std::vector<double>& data,
               const std::string& units,
               const std::string& description);
  /// A dataset of doubles of shape {rows, trailing...} that grows by AppendRows (rows
  /// unknown in advance: extendable along the first axis, stored in chunks of
  /// kChunkRows rows, which readers do not see). Returns its handle for AppendRows.
  std::size_t GrowingDoubles(const std::string& dataset,
                             const std::vector<std::size_t>& trailing,
                             const std::string& units,
                             const std::string& description);
  /// Appends `rows` rows to a GrowingDoubles dataset: `data` holds them, row-major
  /// (rows times the row width values).
  void AppendRows(std::size_t handle, const std::vector<double>& data, std::size_t rows);
  /// A 1-D dataset of 64-bit integers.
  void Integers(const std::string& dataset,
                const std::vector<long long>& data,
                const std::string& units,
                const std::string& description);
  /// A 1-D dataset of variable-length UTF-8 strings (units "none"). Invalid UTF-8 in a
  /// value is written as U+FFFD (see ValidUtf8).
  void Strings(const std::string& dataset,
               const std::vector<std::string>& values,
               const std::string& description);
  /// A string attribute on the root ("/") or on a group or dataset already written
  /// (invalid UTF-8 as in Strings).
  void Attribute(const std::string& object, const std::string& name, const std::string& value);

  /// Completes and closes the HDF5 file, still under its temporary name (then only
  /// Commit() is allowed). Throws std::runtime_error on failure.
  void Close();
  /// Close() if not done, then renames the file onto `path`. Throws std::runtime_error on
  /// failure.
  void Commit();

  /// Rows per chunk of a GrowingDoubles dataset (fewer for wide rows: a chunk holds at
  /// most 1 MiB).
  static constexpr std::size_t kChunkRows = 4096;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// `s` with every invalid UTF-8 sequence (stray continuation bytes, truncated or
/// overlong sequences, surrogates, code points above U+10FFFF) replaced by U+FFFD, the
/// Unicode replacement character, each maximal invalid subpart by one U+FFFD (Unicode
/// 15, 3.9 "U+FFFD Substitution of Maximal Subparts"). Valid text is returned unchanged.
std::string ValidUtf8(const std::string& s);

}  // namespace deploysim::io
