#pragma once

/// Exact versus quasi-rigid coupling (docs/design.md 2.5): runs a geometry-mode profile
/// twice, with h_rel from the hinge rates and with h_rel = 0 (the seed's instantaneously
/// rigid body), on the same output grid, and measures the difference. The angular-velocity
/// difference during deployment scales with the hinge rate; the attitude offset at the
/// end of deployment is a geometric phase set by the total swing, not its speed.

#include "deploysim/run/mission.h"

namespace deploysim::run {

struct CouplingComparison {
  MissionResult exact;
  MissionResult quasi_rigid;
  double max_w_difference_deploying = 0.0;  ///< [rad/s] max |w_exact - w_qr| within move stages.
  double w_scale = 0.0;                     ///< [rad/s] max |w_exact| (for relative numbers).
  double deployment_end = 0.0;              ///< [s] end of the last move stage.
  double attitude_offset_at_deployment_end = 0.0;  ///< [rad] angle between the attitudes there.
  double max_attitude_difference_after = 0.0;      ///< [rad] after the deployment.
  double max_H_B_difference_after = 0.0;           ///< relative to |H|, after the deployment.
};

/// Requires geometry mode (throws std::invalid_argument otherwise). The profile's own
/// coupling is ignored: both are run.
CouplingComparison CompareCouplings(const schedule::Profile& profile);

}  // namespace deploysim::run
