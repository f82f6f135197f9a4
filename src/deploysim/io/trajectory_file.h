#pragma once

/// Trajectory output (docs/design.md 5, docs/file_formats.md "Trajectory files"): an HDF5
/// file readable by h5py, MATLAB h5read and h5dump, and an optional CSV. Both are written
/// atomically (AtomicFile): on any failure nothing is left at `path` (an existing file
/// there is kept unchanged) and no temporary remains.
///
/// HDF5 layout (schema_version 2): row-major datasets of IEEE little-endian doubles
/// (counts and indices: 64-bit integers), each with string attributes `units` and
/// `description`; text as variable-length UTF-8 strings. Quaternions scalar first (w, x, y, z);
/// J_B[n][i][j] = J_B(i, j) at time n. Free hinges add /hinge_rates,
/// /energy_spring, /energy_total, /panel_names, /hinge_latch_time, the hinge event table
/// /events/hinge/*, /events/spin_axis_45_time and the stage columns caveat and
/// rigid_body_only (docs/file_formats.md, "Hinge events").

#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deploysim/io/trajectory_csv.h"
#include "deploysim/run/danger_windows.h"
#include "deploysim/run/mission.h"
#include "deploysim/run/stage_table.h"
#include "deploysim/run/trajectory_schema.h"

namespace deploysim::io {

/// Version of the HDF5 layout written by WriteTrajectoryFile (root attribute
/// `schema_version`); bumped on any incompatible change.
/// Version 2: /energy is the total kinetic energy (was 1/2 w.J w), /energy_rigid, the
/// per-stage analysis in /stages, /danger_windows, /events/predicted_flip_time and the
/// model_source and model_text attributes.
/// The root attribute `body` (the expanded body of a hinged model, io/body_json.h) is an
/// addition to version 2 as well: readers of older files draw from model_text instead.
///
/// The free-hinge outputs are additions to version 2, not a version 3: no
/// dataset or attribute of version 2 changed its name, shape, type, units or meaning
/// (/energy is still the kinetic energy; the stored spring energy is the new
/// /energy_spring and their sum the new /energy_total), so every reader of version 2
/// files (h5py, MATLAB, h5dump, ReadTrajectoryFile of earlier deploysim builds) reads the
/// new files unchanged and simply does not see the new datasets. For a hinge profile the
/// rows of /stages are the phases between hinge events instead of the profile's stages
/// (a hinge profile has no `stages:`), with empty /stages/from and /stages/to: the same
/// columns with the same meaning per row. ReadTrajectoryFile reads version 2 files
/// written before those additions too: the new datasets are optional, and where a file has none
/// of them the corresponding fields are left empty (TrajectoryFile::has_hinge_outputs
/// is false).
inline constexpr int kTrajectorySchemaVersion = 2;

/// One row of the stage table /stages/* (run::StageTable).
using StageRow = run::StageRow;

/// One row of the hinge event table /events/hinge/* (run::HingeEvent).
struct HingeEventRow {
  run::HingeEvent event;   ///< Kind read back from its name ("latch", ...).
  std::string panel_name;  ///< Name of panel event.panel in the model.
};

/// The contents of a trajectory file, as read back.
struct TrajectoryFile {
  /// hinge_angles and hinge_rates empty unless the file has them (geometry mode);
  /// energy_spring empty only in files written before the free-hinge outputs.
  run::Trajectory trajectory;
  std::vector<double> flip_times;                 ///< [s] /events/flip_time
  std::vector<double> predicted_flip_times;       ///< [s] /events/predicted_flip_time
  std::vector<StageRow> stages;                   ///< /stages/*
  std::vector<run::DangerWindow> danger_windows;  ///< /danger_windows/*
  /// The derived columns of the schema read (run::TrajectorySchema), flat row-major
  /// by name: "energy_total" (trajectory.energy + trajectory.energy_spring, as written)
  /// where the file has the free-hinge outputs.
  std::map<std::string, std::vector<double>> derived;
  /// /panel_names: the model's panel names in panel order (geometry mode).
  std::vector<std::string> panel_names;
  std::vector<HingeEventRow> hinge_events;  ///< /events/hinge/*, in time order.
  /// [s] /hinge_latch_time: per panel, when it locked (latch, jam or rest on a stop);
  /// NaN if never. Empty for stage profiles.
  std::vector<double> hinge_latch_times;
  std::vector<double> spin_axis_45_times;  ///< [s] /events/spin_axis_45_time
  /// False for a version 2 file written before the free-hinge outputs (none of the datasets above,
  /// nor /stages/caveat and /stages/rigid_body_only).
  bool has_hinge_outputs = false;
  /// Root attributes (all strings): deploysim_version, schema_version, profile_name,
  /// profile_source, profile_text, model_name, model_source, model_text, integrator,
  /// integrator_settings, mode, coupling, termination, termination_message, statistics,
  /// max_h_N_drift, outcome and warnings (JSON), and for a hinged model body (JSON,
  /// io/body_json.h; absent in files written before it).
  std::map<std::string, std::string> attributes;
  /// `units` attribute of every dataset, by absolute path ("/H_B", "/events/flip_time").
  std::map<std::string, std::string> units;
};

/// Writes r (its profile and model texts, trajectory, flip times, stage table with the
/// per-stage analysis, danger windows, hinge events and latch times) to `path`. Throws
/// std::invalid_argument if the trajectory's arrays do not all have one entry per output
/// time (hinge angles and rates: in geometry mode, one per panel), r.stages does not have
/// one report per profile stage (hinge profiles: any number of phases), r.latch_times is
/// neither empty nor one per panel, or a hinge event names no panel of the model; and
/// std::runtime_error naming `path` for I/O failures. The same file as a
/// TrajectoryFileWriter fed r.trajectory (it is one).
/// The per-sample datasets are the columns of `schema` (which must outlive the call).
void WriteTrajectoryFile(const std::string& path,
                         const run::MissionResult& r,
                         const run::TrajectorySchema& schema = run::TrajectorySchema::Standard());

/// A trajectory file written while the mission runs (memory bounded by the block size
/// whatever the horizon): the per-sample datasets grow block by block, the rest is
/// written by Finish; then Commit() puts the file at `path` (atomically: until then, and
/// if anything fails, nothing is left at `path` and an older file there is kept).
/// The file is the same as WriteTrajectoryFile's for readers (the per-sample datasets
/// are stored in chunks, extendable along time; names, shapes, types and attributes are
/// unchanged).
class TrajectoryFileWriter final : public run::SampleSink {
 public:
  /// Starts the temporary and the per-sample datasets for `profile` (hinge angles in
  /// geometry mode), one per column of `schema` (which must outlive the writer). Throws
  /// std::runtime_error naming `path`.
  TrajectoryFileWriter(const std::string& path,
                       const schedule::Profile& profile,
                       const run::TrajectorySchema& schema = run::TrajectorySchema::Standard());
  ~TrajectoryFileWriter() override;
  TrajectoryFileWriter(const TrajectoryFileWriter&) = delete;
  TrajectoryFileWriter& operator=(const TrajectoryFileWriter&) = delete;

  /// Appends the samples of `block` (checked as WriteTrajectoryFile checks a trajectory).
  void Append(const run::Trajectory& block) override;
  /// Writes events, stages, danger windows and attributes from r (r.trajectory is not
  /// used: the samples are those appended) and completes the temporary.
  void Finish(const run::MissionResult& r);
  /// After Finish: renames the complete file onto `path`.
  void Commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The outputs of `deploysim simulate`: the HDF5 file and, if `csv_path` is not empty,
/// its CSV, streamed side by side. Guarantee: both temporaries are written completely
/// and flushed to disk (Finish) before either replaces anything (Commit); a failure up
/// to then (disk full, file size limit, a signal, an exception) leaves both targets as
/// they were and no temporary. Commit() renames the HDF5 file, then the CSV: only a
/// failure of that last rename (the CSV's target turned into a folder after the
/// checks, a read-only remount in between) can leave the new HDF5 beside an old CSV.
class TrajectoryOutputs final : public run::SampleSink {
 public:
  TrajectoryOutputs(const std::string& h5_path,
                    const std::string& csv_path,
                    const schedule::Profile& profile);
  void Append(const run::Trajectory& block) override;
  void Finish(const run::MissionResult& r);
  void Commit();

 private:
  TrajectoryFileWriter h5_;
  std::optional<TrajectoryCsvWriter> csv_;
};

/// Reads a file written by WriteTrajectoryFile (or by a deploysim from before the free-hinge
/// outputs: see kTrajectorySchemaVersion). Throws std::runtime_error naming `path` and the dataset
/// for unreadable files, missing datasets, wrong shapes, an unknown hinge event kind or
/// another schema_version. Reads the columns of `schema`.
TrajectoryFile ReadTrajectoryFile(
    const std::string& path,
    const run::TrajectorySchema& schema = run::TrajectorySchema::Standard());

}  // namespace deploysim::io
