#pragma once

/// Trajectories as CSV: the whole trajectory at once (WriteTrajectoryCsv), or streamed
/// while the mission runs (TrajectoryCsvWriter); both atomic, the columns those of an
/// run::TrajectorySchema.

#include <cstddef>
#include <memory>
#include <string>

#include "deploysim/run/mission.h"
#include "deploysim/run/trajectory_schema.h"

namespace deploysim::io {

/// The CSV of WriteTrajectoryCsv, written while the mission runs; atomic as
/// TrajectoryFileWriter (Finish completes the temporary, Commit renames it).
class TrajectoryCsvWriter final : public run::SampleSink {
 public:
  /// `hinge_columns`: hinge angles (and as many hinge rates) per sample (0: none); one
  /// CSV column per component of each column of `schema` (which must outlive the writer).
  TrajectoryCsvWriter(
      const std::string& path,
      std::size_t hinge_columns,
      const run::TrajectorySchema& schema = run::TrajectorySchema::Standard());
  ~TrajectoryCsvWriter() override;
  TrajectoryCsvWriter(const TrajectoryCsvWriter&) = delete;
  TrajectoryCsvWriter& operator=(const TrajectoryCsvWriter&) = delete;

  void Append(const run::Trajectory& block) override;
  void Finish();
  void Commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes the trajectory as CSV: one header line of column names with units in brackets
/// ("time [s],H_B_x [kg m^2/s],..."), then one line per output time, numbers in the
/// shortest form that reads back exactly. The columns are those of `schema`
/// (run::TrajectorySchema: the standard one lists time, H_B_{x,y,z},
/// w_NB_B_{x,y,z}, q_NB_{w,x,y,z}, J_B_{xx,yy,zz,xy,xz,yz}, principal_moments_{1,2,3},
/// h_rel_B_{x,y,z}, h_N_{x,y,z}, energy, energy_rigid,
/// euler_313_{precession,nutation,spin}, spin_axis_angle, hinge_angle_{0..P-1},
/// energy_spring, energy_total, hinge_rate_{0..P-1}: the free-hinge columns after the
/// older ones, which keep their positions). Same atomicity and errors as
/// WriteTrajectoryFile.
void WriteTrajectoryCsv(
    const std::string& path,
    const run::Trajectory& trajectory,
    const run::TrajectorySchema& schema = run::TrajectorySchema::Standard());

}  // namespace deploysim::io
