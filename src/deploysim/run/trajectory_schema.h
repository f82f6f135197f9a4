#pragma once

/// The trajectory's columns, stated once. Every output of the sampled trajectory is
/// derived from this table: the HDF5 datasets (name, shape, units, description) and
/// their reader, the CSV columns, the Python package's numpy arrays, the JSON of the last
/// sample, the size checks and the in-memory bookkeeping of Trajectory blocks. Adding a
/// column is one entry here: a stored one also needs its member in Trajectory and the
/// recorder's line that fills it; a derived one (computed from the stored ones, like
/// energy_total) needs nothing else.

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "deploysim/run/mission.h"

namespace deploysim::run {

/// The values of one column at one sample.
enum class ColumnShape {
  kScalar,      ///< 1 value
  kVector3,     ///< 3 values (x, y, z or as the column names them)
  kQuaternion,  ///< 4 values, scalar first (w, x, y, z)
  kMatrix3,     ///< 9 values, row-major: [i][j] = M(i, j)
  kPerPanel,    ///< one value per panel, in panel order (geometry mode)
};

/// Access to the Trajectory member a stored column lives in (type-erased: one
/// implementation per member type, made by the schema's table).
class ColumnStorage {
 public:
  virtual ~ColumnStorage() = default;
  /// Entries of the member (one per sample when consistent).
  virtual std::size_t size(const Trajectory& t) const = 0;
  /// Values in the row of sample k (a per-panel row: its own length).
  virtual std::size_t width(const Trajectory& t, std::size_t k) const = 0;
  virtual void clear(Trajectory& t) const = 0;
  /// Appends every entry of `from` to `to`.
  virtual void append(Trajectory& to, const Trajectory& from) const = 0;
  /// Keeps entry k of `from` alone in `to` (no entry if `from` has none).
  virtual void keep(Trajectory& to, const Trajectory& from, std::size_t k) const = 0;
  /// Appends one sample from its `width` flat values (as `values` writes them).
  virtual void push(Trajectory& t, const double* row, std::size_t width) const = 0;
};

struct TrajectoryColumn {
  std::string name;  ///< HDF5 dataset /name, numpy key, JSON key
  std::string units;
  std::string description;
  ColumnShape shape = ColumnShape::kScalar;
  /// CSV: scalars are one column "name [units]"; other shapes one column per component,
  /// "<csv_prefix>_<component> [units]", component names and flat indices below (per
  /// panel: the panel index, every value).
  std::string csv_prefix;
  std::vector<std::string> csv_components;
  std::vector<int> csv_indices;
  /// Added to version 2 with the free-hinge outputs: absent from files written before.
  bool free_hinge_output = false;
  /// Added to version 2 with the energy ledger: absent from files written before.
  bool ledger_output = false;
  /// Writes the row of sample k of t (Width values) to `row`.
  std::function<void(const Trajectory& t, std::size_t k, double* row)> values;
  /// Stored columns: the member. Null for a derived column (computed by `values` from
  /// the stored ones; read back into TrajectoryFile::derived).
  std::shared_ptr<const ColumnStorage> storage;
};

/// Values per sample of column c with `panels` panels.
std::size_t Width(const TrajectoryColumn& c, std::size_t panels);
/// The shape of one sample's values: {}, {3}, {4}, {3, 3} or {panels}.
std::vector<std::size_t> RowShape(const TrajectoryColumn& c, std::size_t panels);

class TrajectorySchema {
 public:
  /// deploysim's trajectory, in CSV column order (time first).
  static const TrajectorySchema& Standard();

  const std::vector<TrajectoryColumn>& columns() const { return columns_; }
  /// Appends a column. Throws std::invalid_argument for an empty or repeated name, a
  /// derived column without values, or CSV components that do not fit the shape.
  void Add(TrajectoryColumn c);
  /// The columns a run writes: per-panel ones only when `per_panel`.
  std::vector<const TrajectoryColumn*> Written(bool per_panel) const;

  /// Every stored column of t has one entry per output time and, if `panels` is not 0,
  /// the per-panel ones `panels` values per entry (if 0, they are not checked). Throws
  /// std::invalid_argument naming `what`, the member and the rule.
  void Check(const std::string& what, const Trajectory& t, std::size_t panels) const;
  /// Empties every stored member of t.
  void Clear(Trajectory& t) const;
  /// Appends every stored member of `from` to `to`.
  void Append(Trajectory& to, const Trajectory& from) const;
  /// Sample k of `from` alone.
  Trajectory Row(const Trajectory& from, std::size_t k) const;

 private:
  std::vector<TrajectoryColumn> columns_;
};

/// Panels per sample of t: the length of its first hinge-angle row (0 if none).
std::size_t PanelCount(const Trajectory& t);

}  // namespace deploysim::run
