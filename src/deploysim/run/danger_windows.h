#pragma once

/// The danger window table, described once: the intervals of the output grid in which the
/// spin axis is the intermediate principal axis of J_B(t) (flips possible). The HDF5
/// group /danger_windows, its reader, `analyze --json`'s "danger_windows" and the Python
/// package's table are all derived from DangerWindowTable (docs/design.md 4, "Records
/// described once").

#include <functional>
#include <string>
#include <vector>

#include "deploysim/run/mission.h"

namespace deploysim::run {

/// One column of the danger window table (a real number per window).
struct DangerWindowColumn {
  std::string name;         ///< HDF5 dataset /danger_windows/<name>, JSON and Python key
  std::string units;        ///< as the HDF5 `units` attribute
  std::string description;  ///< as the HDF5 `description` attribute
  std::function<double(const DangerWindow& w)> value;
  /// The reader: the value read back into the window (null: derived from other columns).
  std::function<void(DangerWindow& w, double v)> set;
};

/// The danger window table: the standard columns in file order, and Extend (a column
/// added by a test or an extension before any output is written reaches every output).
class DangerWindowTable {
 public:
  static const std::vector<DangerWindowColumn>& Columns();
  static void Extend(DangerWindowColumn column);
};

}  // namespace deploysim::run
