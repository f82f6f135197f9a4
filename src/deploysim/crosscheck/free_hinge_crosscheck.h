#pragma once

/// The Simbody cross-check of a hinge profile: the reduced free-hinge model
/// (run::RunMission with an run::HingeBody) against the independent Simbody model of
/// simbody_free_hinges.h, from the same initial state on the same output grid. Compared:
///   trajectories: H_B / |H_B(t0)|, attitude [rad], w_NB_B [rad/s] (CompareTrajectories);
///   events, paired in time order (kind and panel must match): time [s], impulse lambda
///     and hub angular-velocity jump (relative to the Simbody value), energy dissipated;
///   latch times per panel [s]; flips [s]; the spin axis's 45-degree crossings (relative).
/// Simbody's own error is reported beside them when asked: Simbody at a looser accuracy
/// (`own_error_accuracy`, e.g. 1e-12) against Simbody at `accuracy` (e.g. 1e-14), the same
/// quantities: an estimate of the error of the looser run, and a bound on the tighter one's.

#include <optional>
#include <string>
#include <vector>

#include "deploysim/crosscheck/crosscheck.h"
#include "deploysim/crosscheck/simbody_free_hinges.h"
#include "deploysim/run/mission.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::crosscheck {

struct FreeHingeCrosscheckOptions {
  double accuracy = 1e-14;  ///< Simbody's accuracy, in (0, 1).
  /// Also run Simbody at this (looser) accuracy and report it against the run at
  /// `accuracy`: Simbody's own error. 0: not run.
  double own_error_accuracy = 0.0;
  std::optional<double> t_end;      ///< [s] run only to here (default: the profile's end).
  std::optional<double> output_dt;  ///< [s] overrides the profile's output.dt.
};

/// Events and their times of two runs, paired in time order.
struct EventComparison {
  bool same_sequence = false;   ///< Same number, kinds and panels in the same order.
  double max_time = 0.0;        ///< [s] max |t_a - t_b|
  double max_impulse = 0.0;     ///< max |lambda_a - lambda_b| / max(|lambda_b|) over events
  double max_w_jump = 0.0;      ///< max |dw_a - dw_b| / max |dw_b| over events
  double max_energy = 0.0;      ///< max |dE_a - dE_b| / max |dE_b| over events
  double max_latch_time = 0.0;  ///< [s] per panel; +inf if one latched and the other not
};

/// Compares a's events with b's (b the reference). Releases at the start are skipped on
/// both sides.
EventComparison CompareEvents(const std::vector<run::HingeEvent>& a,
                              const std::vector<double>& a_latch_times,
                              const std::vector<run::HingeEvent>& b,
                              const std::vector<double>& b_latch_times,
                              double t_begin);

/// Max |t_a - t_b| / |t_b| over the 45-degree crossings paired in order (+inf if the
/// counts differ; 0 if there are none).
double MaxCrossingDifference(const std::vector<double>& a, const std::vector<double>& b);

struct FreeHingeCrosscheckResult {
  schedule::Profile profile;  ///< As run.
  double accuracy = 0.0;
  run::MissionResult reduced;
  SimbodyFreeHingeRun simbody;
  TrajectoryDifference difference;           ///< reduced vs Simbody
  double max_flip_difference = 0.0;          ///< [s]; +inf if the counts differ
  EventComparison events;                    ///< reduced vs Simbody
  double max_45_crossing_difference = 0.0;   ///< relative
  double max_energy_difference = 0.0;        ///< |E_reduced - E_simbody| / E(t0), total energy
  std::vector<double> simbody_45_crossings;  ///< [s] Simbody's (increasing and decreasing)
  /// Simbody's own error (own_error_accuracy > 0): Simbody at own_error_accuracy vs at
  /// `accuracy`.
  bool has_reference = false;
  double own_error_accuracy = 0.0;
  TrajectoryDifference simbody_self;
  double simbody_self_flip_difference = 0.0;
  EventComparison simbody_self_events;
  double simbody_self_45_crossing_difference = 0.0;
};

/// Runs both models (and the Simbody reference if asked). Throws std::invalid_argument for
/// a profile that is not a hinge profile or bad options, std::runtime_error if an
/// integration fails.
FreeHingeCrosscheckResult RunFreeHingeCrosscheck(const schedule::Profile& profile,
                                                 const FreeHingeCrosscheckOptions& options);

/// The result as a CrosscheckResult (reduced, Simbody trajectory and flips, differences)
/// for the cross-check file writer (crosscheck_file.h).
CrosscheckResult AsCrosscheckResult(const FreeHingeCrosscheckResult& r);

/// A fixed-width text table (one quantity per line, with units and Simbody's own error
/// beside each figure when available), for the CLI.
std::string FormatFreeHingeCrosscheckTable(const FreeHingeCrosscheckResult& r);

}  // namespace deploysim::crosscheck
