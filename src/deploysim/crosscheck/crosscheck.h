#pragma once

/// The Simbody cross-check of a deployment profile (docs/design.md 3): the reduced
/// model (run::RunMission, exact coupling) and the Simbody multibody model
/// (simbody_satellite.h) run from the same initial attitude and momentum on the same
/// output grid, and are compared sample by sample:
///   H_B:      |H_B,reduced - H_B,simbody| / |H_B(t0)|          (relative, max over the grid)
///   attitude: angle of q_NB,reduced^-1 q_NB,simbody            [rad]
///   w:        |w_NB_B,reduced - w_NB_B,simbody|                [rad/s]
///   flips:    |t_reduced - t_simbody| pairwise in time order    [s] (counts must match)
/// Simbody's own error is reported beside them: its momentum drift
/// max |h_N(t) - h_N(t0)| / |h_N(t0)|, and for a constant-inertia run (one hold, or a
/// tensor-mode rigid body such as the wing nut) both sides against the closed-form
/// solution (analysis::FreeBodySolution), flips included.

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "deploysim/crosscheck/simbody_satellite.h"
#include "deploysim/run/mission.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::crosscheck {

struct CrosscheckOptions {
  double accuracy = 1e-12;  ///< Simbody RK-Merson accuracy, in (0, 1).
  /// Run only up to this time [s] (shorter horizons for tests); it must fall inside a
  /// hold stage or on a stage end (a move stage cannot be cut: its law is normalized by its
  /// duration). Default: the profile's end.
  std::optional<double> t_end;
  std::optional<double> output_dt;  ///< [s] overrides the profile's output.dt.
};

/// Sample-by-sample differences of two trajectories on the same grid.
struct TrajectoryDifference {
  std::vector<double> H_B_relative;  ///< |dH_B| / |H_B(t0)|
  std::vector<double> attitude;      ///< [rad]
  std::vector<double> w;             ///< [rad/s] |dw_NB_B|
  double max_H_B_relative = 0.0;
  double max_attitude = 0.0;
  double max_w = 0.0;    ///< [rad/s]
  double w_scale = 0.0;  ///< [rad/s] max |w_NB_B| of the reference (Simbody)
};

/// Differences between the reduced trajectory and Simbody's (same grid; throws
/// std::invalid_argument if the sizes or times differ).
TrajectoryDifference CompareTrajectories(const run::Trajectory& reduced,
                                         const SimbodyTrajectory& simbody);

/// Max |a_k - b_k| over flips paired in time order; +inf if the counts differ, 0 if none.
double MaxFlipDifference(const std::vector<double>& a, const std::vector<double>& b);

struct CrosscheckResult {
  schedule::Profile profile;  ///< As run: exact coupling (geometry mode), horizon, output dt.
  double accuracy = 0.0;      ///< Simbody accuracy.
  run::MissionResult reduced;
  SimbodyRun simbody;
  TrajectoryDifference difference;
  double max_flip_difference = 0.0;  ///< [s] reduced vs Simbody; +inf if the counts differ.
  /// Constant-inertia runs only (has_analytic): the closed-form solution from the same
  /// initial state.
  bool has_analytic = false;
  std::vector<double> analytic_flip_times;            ///< [s]
  double max_flip_difference_simbody_analytic = 0.0;  ///< [s]
  double max_flip_difference_reduced_analytic = 0.0;  ///< [s]
  double simbody_max_analytic_error = 0.0;            ///< max |H_B,simbody - H_B,analytic| / |H|
  double reduced_max_analytic_error = 0.0;            ///< max |H_B,reduced - H_B,analytic| / |H|
};

/// The default agreement tolerance of a cross-check (CrosscheckVerdict).
inline constexpr double kDefaultAgreementTolerance = 1e-4;

/// Whether the reduced model and Simbody agree: the same flips (and, for a hinge profile,
/// the same sequence of hinge events: kinds, panels, order), and every difference within
/// `tolerance`: H_B relative to |H_B(t0)|, w_NB_B relative to Simbody's largest |w|, and
/// flip and event times relative to the run's length. `reason`: the first rule broken.
struct CrosscheckVerdict {
  bool agree = true;
  std::string reason;
  double tolerance = kDefaultAgreementTolerance;
};

/// The verdict from a comparison: `events_same` false when the hinge events differ,
/// `max_event_time` the largest event-time difference [s] (0 without events),
/// max_flip_difference +inf when the flip counts differ.
CrosscheckVerdict Judge(const TrajectoryDifference& difference,
                        double max_flip_difference,
                        bool events_same,
                        double max_event_time,
                        double duration,
                        double tolerance);

/// "verdict: agree (...)" or "verdict: DISAGREE: <reason> (...)", one line.
std::string FormatVerdict(const CrosscheckVerdict& verdict);

/// The profile cut at t_end (see CrosscheckOptions::t_end); throws std::invalid_argument
/// if t_end is outside (t_begin, t_end] or inside a move stage.
schedule::Profile TruncateProfile(const schedule::Profile& profile, double t_end);

/// Runs both models and compares them. Geometry mode is run with exact coupling whatever
/// the profile says (the multibody model has the panels' relative momentum); tensor mode
/// needs a constant inertia. Throws std::invalid_argument for bad options or a profile
/// the cross-check cannot represent, std::runtime_error if an integration fails.
CrosscheckResult RunCrosscheck(const schedule::Profile& profile, const CrosscheckOptions& options);

/// A fixed-width text table of the result (one quantity per line, with units), for the CLI.
std::string FormatCrosscheckTable(const CrosscheckResult& result);

}  // namespace deploysim::crosscheck
