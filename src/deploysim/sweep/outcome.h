#pragma once

/// The outcome of one sweep case, computed on a lean path: the same schedule, stepper,
/// tolerances and flip rule as analysis::RunMission, but without the dense trajectory on
/// the output grid (which costs most of a mission run: one partial step per sample).
/// Only the accepted steps and two kinds of located events are evaluated:
///   - flips: sign changes of H_B along the spin axis while it is the intermediate
///     principal axis of J_B(t), located and filtered exactly as RunMission does;
///   - extrema of s . H_B (zeros of its rate s . (H_B x w_NB_B)), where the angle
///     between the body spin axis s and h_N is largest or smallest.
/// The largest angle is the maximum over the start, every accepted step and every
/// located extremum, so it is the true maximum to the integrator's accuracy.
///
/// Final motion class, from the final state (t_end) and J_B(t_end): the torque-free
/// motion that would follow (FreeBodySolution's regime). The momentum circulates about
/// the minor or major principal axis on a cone; its largest half-angle is
///   minor: acos(|h1|min / M), |h1|min^2 = h1^2 - h3^2 I1 (I3 - I2) / (I3 (I2 - I1)),
///   major: acos(|h3|min / M), |h3|min^2 = h3^2 - h1^2 I3 (I2 - I1) / (I1 (I3 - I2)),
/// (principal components h, moments I1 < I2 < I3, formed without cancellation of 2T I2 - M^2).
/// Cone <= tumble_angle: "spin-minor" / "spin-major"; wider, or the separatrix: "tumbling";
/// H_B along the intermediate axis: "spin-intermediate" (an unstable equilibrium).
/// An axisymmetric body spins about its symmetry axis (minor or major), a spherical one
/// about H_B.

#include <cstdint>
#include <string>

#include "deploysim/integrators/integrate.h"
#include "deploysim/sweep/sweep_spec.h"

namespace deploysim::sweep {

enum class MotionClass : std::int32_t {
  kSpinMinor = 0,         ///< Spin about the minor axis, cone <= tumble angle.
  kSpinMajor = 1,         ///< Spin about the major axis, cone <= tumble angle.
  kSpinIntermediate = 2,  ///< H_B along the intermediate axis (unstable equilibrium).
  kTumbling = 3,          ///< Wider cone, or on the separatrix.
  kFailed = 4,            ///< The integration did not reach the end.
};
/// "spin-minor", "spin-major", "spin-intermediate", "tumbling", "failed".
std::string ToString(MotionClass c);

/// What one case produced. Every field except run_time is a deterministic function of
/// the case (bit-identical across threads, ranks and runs).
struct CaseOutcome {
  integrators::Termination termination = integrators::Termination::kReachedEnd;
  std::int64_t flip_count = 0;
  double first_flip_time = 0.0;        ///< [s] NaN when there is no flip.
  double max_spin_axis_angle = 0.0;    ///< [rad] largest angle between s and h_N.
  double final_spin_axis_angle = 0.0;  ///< [rad] at t_end.
  MotionClass final_class = MotionClass::kFailed;
  /// Body axis nearest the final circulation axis, signed along the momentum:
  /// 0..2 = +x, +y, +z; 3..5 = -x, -y, -z.
  std::int32_t final_axis = 0;
  std::int32_t final_regime = 0;  ///< analysis::Regime as an integer.
  double final_cone_angle = 0.0;  ///< [rad] half-angle of the final momentum cone.
  double energy_initial = 0.0;    ///< [J] total kinetic energy at t0 (TotalKineticEnergy).
  double energy_final = 0.0;      ///< [J] at t_end.
  double deploy_end_time = 0.0;   ///< [s] end of the last move stage (t0 if none).
  double deploy_duration = 0.0;   ///< [s] total duration of the move stages.
  double end_time = 0.0;          ///< [s] t_end of the case.
  std::int64_t steps = 0;         ///< Accepted integrator steps.
  std::int64_t rejected = 0;      ///< Rejected step attempts.
  double run_time = 0.0;          ///< [s] wall time of the case (not deterministic).
};

/// "+x", "+y", "+z", "-x", "-y", "-z".
std::string AxisName(std::int32_t final_axis);

/// Runs one case on the lean path. Thread-safe: everything it touches is its own (one
/// stepper per call). Throws std::invalid_argument for invalid settings.
CaseOutcome SimulateOutcome(const Case& c, const OutcomeSettings& settings);

}  // namespace deploysim::sweep
