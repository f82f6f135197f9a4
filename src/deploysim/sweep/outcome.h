#pragma once

/// The outcome of one sweep case: the case's mission run (run::RunMission) without
/// output samples (RunOptions::sample_trajectory = false: the dense trajectory on the
/// output grid costs most of a full run, one partial step per sample). The run's flips,
/// 45-degree crossings, largest spin-axis angle (located exactly, run_recorder.h), hinge
/// events, energies and final state are those of `simulate` and `analyze`, bit for bit.
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
///
/// Outcomes that do not depend on the simulated horizon, from the same torque-free motion
/// after the end (J_B(t_end), H_B(t_end); exact when nothing moves after the end):
///   - the separatrix distance (D - I2) / (I3 - I1), D = M^2 / (2T): < 0 circulating about
///     the minor axis, > 0 about the major axis, 0 on the separatrix (and for a pure spin
///     about the intermediate axis). Formed without cancellation from FreeBodySolution's
///     1 - k^2 (D - I2 = -P2 / (2T), P2 = (1 - k^2) (I2 - I1) P3 / (I3 - I1) below the
///     separatrix, -(1 - k^2) (I3 - I2) P1 / (I3 - I1) above), so its sign is the regime's;
///   - the predicted time between flips: FreeBodySolution::flip_half_period() when the
///     body spin axis s is then the intermediate principal axis (the flip rule,
///     analysis/flip_rule.h), +inf otherwise. Finite: the body will flip, every that many
///     seconds, however long the final hold (a slow spin that did not flip within the
///     simulated time still will).
///
/// Energies are totals T + V (kinetic plus spring, for hinge profiles).

#include <cstdint>
#include <string>

#include "deploysim/analysis/free_body_solution.h"
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
/// the case (bit-identical across threads, ranks and runs). Its outputs (the journal's
/// record, the results file's columns, the CSV and the Python columns) are derived from
/// CaseOutcomeTable (case_outcome_table.h): a field added here is stored and written once
/// it has its entry there.
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
  /// (D - I2) / (I3 - I1) of the final torque-free motion (NaN: failed, or no separatrix:
  /// three equal moments or at rest).
  double final_separatrix_distance = 0.0;
  /// [s] time between flips of the final torque-free motion (+inf: it will not flip; NaN:
  /// failed).
  double predicted_flip_half_period = 0.0;
  // Hinge profiles only (0 for stage profiles): the hinge events of the run.
  std::int64_t latched_count = 0;  ///< Latch events (a jam or a rest on a stop is not one).
  std::int32_t all_latched = 0;    ///< 1 if latched_count == Case::latches_expected.
  /// [rad/s] largest |hub w jump| over the impulsive hinge events (latch, jam, stop
  /// impact, rest on a stop): the latch shock (or the shock of what caught the panel).
  double max_latch_w_jump = 0.0;
  double max_latch_impulse = 0.0;         ///< [N m s] largest |impulse| over those events.
  double energy_dissipated_events = 0.0;  ///< [J] energy dissipated by all hinge events.
  // The outcome measured from the motion (analysis::MotionOutcome), the verdict `analyze`
  // prints for the same case.
  std::int32_t outcome_class = 0;       ///< analysis::OutcomeClass as an integer.
  std::int32_t outcome_role_phase = 0;  ///< analysis::AxisRole at the final phase's start.
  std::int32_t outcome_role_end = 0;    ///< analysis::AxisRole at the end.
  double outcome_phase_begin = 0.0;     ///< [s] start of the final phase.
  double nutation_rate = 0.0;           ///< [1/s] fitted envelope rate (NaN: no fit).
  double nutation_rate_sigma = 0.0;     ///< [1/s] its standard error (NaN: no fit).
  double linear_growth_rate = 0.0;      ///< [1/s] the linearization's (NaN: no steady spin).
  double transition_time = 0.0;         ///< [s] NaN: no transition.
  double time_to_tumble = 0.0;          ///< [s] MotionOutcome::time_to_tumble.
  std::int32_t time_to_tumble_measured = 0;
  double run_time = 0.0;  ///< [s] wall time of the case (not deterministic).
};

/// Whether the case's final torque-free motion flips, whatever the simulated horizon: a
/// finite predicted_flip_half_period of a run that reached the end.
bool WillFlip(const CaseOutcome& o);

/// "+x", "+y", "+z", "-x", "-y", "-z".
std::string AxisName(std::int32_t final_axis);

/// The case's outcome measured from the motion, by name (analysis::OutcomeName).
std::string OutcomeName(const CaseOutcome& o);

/// Runs one case: its outcome-only mission run. Thread-safe: everything it touches is its own (one
/// stepper per call). Throws std::invalid_argument for invalid settings.
CaseOutcome SimulateOutcome(const Case& c, const OutcomeSettings& settings);

/// The horizon-independent outcomes of the torque-free motion with inertia J_B and
/// momentum H_B, for the body spin axis s (see the file comment).
struct FinalPrediction {
  analysis::Regime regime = analysis::Regime::kAtRest;
  double one_minus_k2 = 0.0;         ///< FreeBodySolution::complementary_parameter().
  double separatrix_distance = 0.0;  ///< (D - I2) / (I3 - I1); NaN without a separatrix.
  double flip_half_period = 0.0;     ///< [s] +inf: no flip.
};
FinalPrediction PredictFinal(const math::Mat3& J_B, const math::Vec3& H_B, const math::Vec3& s);

}  // namespace deploysim::sweep
