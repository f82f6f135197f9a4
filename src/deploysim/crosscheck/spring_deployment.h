#pragma once

/// Spring-driven deployment (how real panels deploy): Simbody releases the hinges
/// at t_begin from the profile's first configuration, torsional springs and dampers
/// swing them open and a stiff stop latches them at the open angle (SpringDrive in
/// simbody_satellite.h). Simbody records the hinge angles, rates and accelerations at
/// every accepted step; the reduced model replays that history with exact coupling
/// (HingeHistorySource: quintic Hermite interpolation, knots as breakpoints) from the same
/// initial attitude and momentum, and the two are compared on the output grid. The
/// replay agrees to the interpolation and integration error (tested:
/// <= 1e-7 relative in H_B).

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "deploysim/run/mission.h"
#include "deploysim/crosscheck/crosscheck.h"
#include "deploysim/crosscheck/simbody_satellite.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::crosscheck {

struct SpringDeploymentOptions {
  SpringDrive drive;
  double accuracy = 1e-12;                   ///< Simbody accuracy
  std::optional<double> t_end;               ///< [s] horizon (default: the profile's end)
  std::optional<double> output_dt;           ///< [s] default: the profile's output.dt
  std::string replay_method = "rkmk-rkf78";  ///< reduced-model integrator (adaptive)
  double replay_rtol = 1e-12;
  double replay_atol = 1e-14;  ///< relative to |H_B(0)|
};

struct SpringDeploymentResult {
  schedule::Profile profile;    ///< as run (horizon, output dt)
  SimbodyRun simbody;           ///< with the hinge history
  run::Trajectory replay;  ///< time, H_B, w_NB_B, q_NB, h_N, J_B, h_rel_B, hinge_angles
  std::vector<double> replay_flip_times;  ///< [s] flips of the replay (as RunMission counts them)
  TrajectoryDifference difference;        ///< replay vs Simbody
  double max_flip_difference = 0.0;       ///< [s] replay vs Simbody; +inf if the counts differ
  std::vector<double> latch_times;  ///< [s] per panel: first arrival at the open angle (NaN: never)
  double replay_max_h_N_drift = 0.0;
  double replay_wall_seconds = 0.0;
  integrators::Statistics replay_stats;
};

/// Throws std::invalid_argument for a non-geometry profile, an unknown `open`
/// configuration or bad drive parameters; std::runtime_error if an integration fails.
SpringDeploymentResult RunSpringDeployment(const schedule::Profile& profile,
                                           const SpringDeploymentOptions& options);

std::string FormatSpringDeploymentTable(const SpringDeploymentResult& result);

}  // namespace deploysim::crosscheck
