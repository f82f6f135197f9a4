#pragma once

/// Deployment-speed study (docs/design.md 2.5): how wrong is the seed thesis's
/// quasi-rigid coupling (h_rel = 0) against the multibody truth (Simbody), as a function
/// of how long the deployment takes?
///
/// For each duration D the study builds, from a geometry-mode base profile (its model,
/// initial state and integrator), the profile
///     hold `from` on [0, hold_before];  `from` -> `to` with `law` over D;  hold `to` for
///     hold_after,
/// where `from` is the base's first configuration and `to` its last, runs Simbody (hinges
/// prescribed) and the reduced model with quasi-rigid and with exact coupling, and
/// measures (quasi-rigid vs Simbody):
///   - max |dw_NB_B| during the deployment [rad/s]: scales with the hinge rate, so it falls
///     roughly as 1/D;
///   - the attitude difference at the end of the deployment [rad]: a geometric phase,
///     int J^-1 h_rel dt, set by the total swing, nearly independent of D;
///   - the max attitude and w differences over the hold after (order one once the spin
///     axis is intermediate: the two models tumble differently).
/// Both statements hold while the deployment passes the danger window (spin axis
/// intermediate) quickly; a deployment that lingers in it lets the instability amplify
/// the difference during the deployment itself (column danger_time_deploying).
/// The exact coupling's differences are the control (they must stay at Simbody's accuracy).

#include <string>
#include <vector>

#include "deploysim/schedule/laws.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::crosscheck {

struct SpeedStudyOptions {
  std::vector<double> durations = {1, 3, 10, 30, 100, 300, 1000};  ///< [s] each > 0
  double hold_before = 10.0;                        ///< [s] > 0, stowed spin before the deployment
  double hold_after = 100.0;                        ///< [s] > 0, deployed spin after it
  double accuracy = 1e-12;                          ///< Simbody accuracy
  double output_dt = 0.1;                           ///< [s] output grid
  schedule::Law law = schedule::Law::kMinimumJerk;  ///< not kStep (exact coupling forbids it)
};

struct SpeedStudyRow {
  double duration = 0.0;  ///< [s]
  /// [s] time within the deployment during which the spin axis is the intermediate axis of
  /// J(t) (the danger window): differences grow exponentially there, so a slow deployment
  /// that lingers in it loses the 1/D fall of the w error.
  double danger_time_deploying = 0.0;
  double max_w_error_deploying = 0.0;     ///< [rad/s] quasi-rigid vs Simbody, during the move
  double w_scale = 0.0;                   ///< [rad/s] max |w| (Simbody) during the move
  double attitude_error_at_end = 0.0;     ///< [rad] quasi-rigid vs Simbody at the move's end
  double max_attitude_error_after = 0.0;  ///< [rad] over the hold after
  double max_w_error_after = 0.0;         ///< [rad/s] over the hold after
  double exact_max_attitude_error = 0.0;  ///< [rad] exact coupling vs Simbody, whole run
  double exact_max_H_B_relative = 0.0;    ///< exact coupling vs Simbody, whole run
  double simbody_momentum_drift = 0.0;    ///< Simbody's own |dh_N|/|h_N|
  double simbody_wall_seconds = 0.0;
  double reduced_wall_seconds = 0.0;  ///< both couplings
};

struct SpeedStudyResult {
  std::string profile_name;  ///< of the base profile
  std::string from, to;      ///< configurations deployed between
  SpeedStudyOptions options;
  std::vector<SpeedStudyRow> rows;  ///< in the order of options.durations
};

/// The study's profile for one duration (see above); `coupling` as given. Throws
/// std::invalid_argument for a non-geometry base or bad options.
schedule::Profile DeploymentProfile(const schedule::Profile& base,
                                    double duration,
                                    const SpeedStudyOptions& options,
                                    schedule::Coupling coupling);

SpeedStudyResult SpeedStudy(const schedule::Profile& base, const SpeedStudyOptions& options);

/// Fixed-width text table, one row per duration.
std::string FormatSpeedStudyTable(const SpeedStudyResult& result);

/// CSV (header with units, one line per duration), written atomically (io::AtomicFile);
/// read by tools/plot_speed_study.py. Throws std::runtime_error naming `path` on failure.
void WriteSpeedStudyCsv(const std::string& path, const SpeedStudyResult& result);

}  // namespace deploysim::crosscheck
