#pragma once

/// The stage table, described once: one row per stage of a stage profile (its name, law
/// and configurations from the profile) or per phase of a hinge profile (between hinge
/// events; no configurations), with the stage's analysis (StageReport). The HDF5 group
/// /stages, its reader, `analyze --json`'s "stages" and the Python package's stage table
/// are all derived from StageTable (docs/design.md 4, "Records described once").

#include <functional>
#include <string>
#include <vector>

#include "deploysim/math/types.h"
#include "deploysim/run/mission.h"

namespace deploysim::run {

/// One row of the stage table.
struct StageRow {
  int index = 0;  ///< Position in the profile (hinge profiles: of the phase), from 0.
  std::string name;
  std::string law;       ///< "hold" or the law's name ("minimum-jerk", ...).
  std::string from;      ///< Configuration at t_begin (empty for a hinge profile's phase).
  std::string to;        ///< Configuration at t_end (empty for a hinge profile's phase).
  double t_begin = 0.0;  ///< [s]
  double t_end = 0.0;    ///< [s]
  bool rigid = false;    ///< J constant and h_rel = 0 over the stage.
  math::Vec3 moments_end = math::Vec3::Zero();  ///< [kg m^2] principal moments at t_end.
  std::string spin_axis_role;        ///< Role of the spin axis at t_end ("intermediate", ...).
  std::string regime;                ///< Rigid stages: the analytic regime; else empty.
  double one_minus_k2 = 0.0;         ///< Rigid stages: 1 - k^2 (0 on the separatrix).
  double separatrix_distance = 0.0;  ///< (D - I2)/(I3 - I1) at t_end.
  double predicted_flip_half_period = 0.0;  ///< [s] +inf when no flips are predicted.
  long long predicted_flip_count = 0;       ///< Analytic flips within the stage.
  long long observed_flip_count = 0;        ///< Located flips within the stage.
  double max_flip_time_difference = 0.0;    ///< [s] |observed - predicted|.
  /// Which conclusions of the stage's verdict hold only for a perfectly rigid body
  /// (StageReport::caveat; empty in files written before the free-hinge outputs).
  std::string caveat;
  /// The spin-axis verdict holds only without energy dissipation
  /// (StageReport::rigid_body_only).
  bool rigid_body_only = false;
  /// Not columns (a file holds the run's flip times instead): the flips of the stage, for
  /// the JSON and Python tables [s].
  std::vector<double> predicted_flips, observed_flips;
};

/// The rows of a result: one per stage report; a stage profile's stage as the profile
/// states it (its reports are one per stage, in its order).
std::vector<StageRow> StageRows(const MissionResult& r);

/// One column of the stage table.
struct StageColumn {
  enum class Type { kReal, kInteger, kFlag, kText, kVector3 };
  std::string name;         ///< HDF5 dataset /stages/<name>, JSON key and Python key
  std::string units;        ///< as the HDF5 `units` attribute ("none" for text)
  std::string description;  ///< as the HDF5 `description` attribute
  Type type = Type::kReal;
  /// The row's value: numbers (one; three for kVector3; 0 or 1 for kFlag) ...
  std::function<void(const StageRow& row, double* out)> number;
  /// ... or text.
  std::function<std::string(const StageRow& row)> text;
  /// Readers: the value read back into the row (null: derived from other columns).
  std::function<void(StageRow& row, const double* in)> set_number;
  std::function<void(StageRow& row, const std::string& in)> set_text;
  /// Where the value does not apply to a row (a phase's configurations, a changing
  /// stage's closed form): JSON null, Python None (text) or NaN (numbers). Null: always
  /// applies. The HDF5 file stores the row's value ("", 0 or +inf) whatever.
  std::function<bool(const StageRow& row)> applies;
  /// In files since the free-hinge outputs only (older files read the row's default).
  bool since_hinge_outputs = false;
  int width() const { return type == Type::kVector3 ? 3 : 1; }
};

/// The stage table: the standard columns in file order, and Extend (a column added by a
/// test or an extension before any output is written reaches every output).
class StageTable {
 public:
  static const std::vector<StageColumn>& Columns();
  static void Extend(StageColumn column);
};

}  // namespace deploysim::run
