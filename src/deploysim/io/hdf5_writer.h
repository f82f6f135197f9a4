#pragma once

/// A new HDF5 file, written atomically (AtomicFile), without HDF5 types in the
/// interface: the one place that knows how deploysim lays out HDF5 (datasets of
/// IEEE little-endian doubles with `units` and `description` attributes, variable-length
/// UTF-8 strings, string attributes). Every writer of HDF5 files (trajectories, sweep
/// results, cross-checks) goes through it, so only io includes HDF5.

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
  /// A 1-D dataset of 64-bit integers.
  void Integers(const std::string& dataset,
                const std::vector<long long>& data,
                const std::string& units,
                const std::string& description);
  /// A 1-D dataset of variable-length UTF-8 strings (units "none").
  void Strings(const std::string& dataset,
               const std::vector<std::string>& values,
               const std::string& description);
  /// A string attribute on the root ("/") or on a group or dataset already written.
  void Attribute(const std::string& object, const std::string& name, const std::string& value);

  /// Closes the file and renames it onto `path`. Throws std::runtime_error on failure.
  void Commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace deploysim::io
