#pragma once

// The run's numpy arrays: the trajectory's, one per column of the trajectory schema
// (run::TrajectorySchema): collected from the run's sample blocks without the GIL,
// handed to numpy without copies.

#include <pybind11/pybind11.h>

#include <cstddef>
#include <vector>

#include "deploysim/run/danger_windows.h"
#include "deploysim/run/mission.h"
#include "deploysim/run/stage_table.h"
#include "deploysim/run/trajectory_schema.h"

namespace deploysim::python {

class TrajectoryArrays final : public run::SampleSink {
 public:
  /// `panels`: per-panel values per sample (geometry mode; else 0); `expected`: samples
  /// to reserve room for. `schema` must outlive the arrays.
  TrajectoryArrays(std::size_t panels,
                   std::size_t expected,
                   const run::TrajectorySchema& schema = run::TrajectorySchema::Standard());
  /// Without the GIL: the block's values, checked as a file writer checks them.
  void Append(const run::Trajectory& block) override;
  /// With the GIL: {name: array (N, *RowShape)} in the schema's order, e.g. (N,), (N, 3),
  /// (N, 4) quaternions w x y z, (N, 3, 3) with [n][i][j] = J(i, j), (N, P).
  pybind11::dict ToDict() &&;

 private:
  const run::TrajectorySchema& schema_;
  std::size_t panels_;
  std::size_t rows_ = 0;
  std::vector<std::vector<double>> flat_;  // per column, row-major
};

/// With the GIL: the run's hinge event table, {name: column} per run::HingeEventTable
/// entry (numbers as arrays (E,) or (E, 3), text as lists).
pybind11::dict HingeEventArrays(const run::MissionResult& r);

/// With the GIL: the run's stage table, one dict per row with a key per run::StageTable
/// column (None for text and NaN for numbers where the column does not apply, as
/// `deploysim analyze --json` writes null; flags as bools, vectors as arrays (3,)), then
/// the stage's predicted_flips and observed_flips [s].
pybind11::list StageRowDicts(const run::MissionResult& r);

/// With the GIL: the run's danger windows, {name: array (W,)} per run::DangerWindowTable
/// column.
pybind11::dict DangerWindowArrays(const run::MissionResult& r);

}  // namespace deploysim::python
