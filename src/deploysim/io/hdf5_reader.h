#pragma once

/// Reading an HDF5 file written by deploysim (Hdf5Writer's layout), without HDF5 types in
/// the interface, so that readers outside io (the sweep results, tools, tests) neither
/// include nor link HDF5. Every error is a std::runtime_error "<path>: <what>".

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace deploysim::io {

class Hdf5Reader {
 public:
  /// What a dataset holds.
  enum class Kind { kFloat, kInteger, kText, kOther };

  /// Opens `path` read-only. Throws "<path>: cannot read: <reason>" or
  /// "<path>: not an HDF5 file".
  explicit Hdf5Reader(const std::string& path);
  ~Hdf5Reader();
  Hdf5Reader(const Hdf5Reader&) = delete;
  Hdf5Reader& operator=(const Hdf5Reader&) = delete;

  const std::string& path() const;

  /// True when `object` ("/cases", "/cases/spin_rate") is a group or dataset of the file.
  bool Exists(const std::string& object) const;
  /// The kind of dataset `dataset`.
  Kind KindOf(const std::string& dataset) const;
  /// The string attributes of `object` ("/" the root, a group or a dataset), by name;
  /// attributes of other types are left out.
  std::map<std::string, std::string> Attributes(const std::string& object) const;
  /// One string attribute (throws when it is missing).
  std::string Attribute(const std::string& object, const std::string& name) const;
  /// A numeric dataset (doubles, or integers converted to double), flattened row-major.
  std::vector<double> Numbers(const std::string& dataset) const;
  /// A dataset of strings, flattened.
  std::vector<std::string> Strings(const std::string& dataset) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace deploysim::io
