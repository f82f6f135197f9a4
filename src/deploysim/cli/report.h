#pragma once

/// Human-readable and JSON reports of a mission (used by `deploysim simulate` and
/// `deploysim analyze`).

#include <string>

#include "deploysim/run/coupling_comparison.h"
#include "deploysim/run/danger_windows.h"
#include "deploysim/run/mission.h"
#include "deploysim/run/stage_table.h"
#include "deploysim/run/trajectory_schema.h"

namespace deploysim::cli {

/// The stability table: one row per stage (a hinge profile: per phase between hinge
/// events), the caveat of each stage's verdict (which conclusions hold only for a
/// perfectly rigid body), then flips, danger windows, invariants.
std::string FormatSummary(const run::MissionResult& r);

/// Hinge profiles: the deployment timeline, one line per hinge event (time, panel, kind,
/// angle [deg], rates before and after [deg/s], impulse [N m s], |hub w jump| [deg/s],
/// energy dissipated [J]), the energy dissipated in all events, when each panel locked
/// and the first 45-degree crossing of the spin axis. Empty for stage profiles.
std::string FormatTimeline(const run::MissionResult& r);

/// The content of FormatSummary and FormatTimeline as a JSON document (SI units: hinge
/// angles in rad, rates in rad/s; "hinge_events", "latch_times" (by panel name, null:
/// never) and "spin_axis_45_crossings" are empty for stage profiles), and "last_sample":
/// the run's last output sample, one member per column of `schema` (null without samples).
std::string FormatJson(const run::MissionResult& r,
                       const run::CouplingComparison* c,
                       const run::TrajectorySchema& schema = run::TrajectorySchema::Standard());

/// Exact vs quasi-rigid coupling, a few lines.
std::string FormatCouplingComparison(const run::CouplingComparison& c);

}  // namespace deploysim::cli
