#pragma once

/// A mission run: profile -> deployment schedule -> integrator -> trajectory on the
/// output grid, flip events, and the stability analysis of every stage (docs/design.md 2.6).

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deploysim/analysis/flip_rule.h"
#include "deploysim/analysis/motion_outcome.h"
#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/math/types.h"
#include "deploysim/run/compiled_run.h"
#include "deploysim/run/hinge_events.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::schedule {
class DeploymentSchedule;
}  // namespace deploysim::schedule

namespace deploysim::run {

/// Where the energy went: the work done on the system since the run's start [J], by
/// source, so that E(t) = E(t0) + sum() (E = T + V, docs/design.md 2.7, "Energy ledger").
struct WorkLedger {
  double damper = 0.0;    ///< the free hinges' dampers (<= 0)
  double friction = 0.0;  ///< their friction (<= 0)
  double motor = 0.0;     ///< their motors and servos
  double drive = 0.0;     ///< the drives that hold prescribed motions (and stage laws)
  double impacts = 0.0;   ///< latches, jams and stop impacts: minus what they dissipate
  double sum() const { return damper + friction + motor + drive + impacts; }
};

/// The sampled trajectory (docs/design.md 5): one entry per output time. Its columns (units,
/// shapes, file and CSV names) are listed once, in trajectory_schema.h.
struct Trajectory {
  std::vector<double> time;                   ///< [s]
  std::vector<math::Vec3> H_B;                ///< [kg m^2/s]
  std::vector<math::Vec3> w_NB_B;             ///< [rad/s]
  std::vector<math::Quat> q_NB;               ///< unit
  std::vector<math::Mat3> J_B;                ///< [kg m^2]
  std::vector<math::Vec3> principal_moments;  ///< [kg m^2] ascending
  std::vector<math::Vec3> h_rel_B;            ///< [kg m^2/s]
  std::vector<math::Vec3> h_N;                ///< [kg m^2/s]
  std::vector<double> energy;                 ///< [J] total kinetic energy (TotalKineticEnergy)
  std::vector<double> energy_rigid;           ///< [J] its rigid-body part 1/2 w.J w
  /// [J] energy stored in the free hinges' springs (hinge profiles; 0 otherwise), every
  /// hinge with a free plan counted, held and latched ones included (their springs still
  /// hold energy), so that energy + energy_spring is continuous at releases.
  std::vector<double> energy_spring;
  std::vector<math::Vec3> euler_313;          ///< [rad] precession, nutation, spin w.r.t. h_N
  std::vector<double> spin_axis_angle;        ///< [rad] initial body spin axis vs h_N
  std::vector<Eigen::VectorXd> hinge_angles;  ///< [rad] geometry mode only (else empty)
  std::vector<Eigen::VectorXd> hinge_rates;   ///< [rad/s] geometry mode only (else empty)
  /// [J] the WorkLedger's entries at each sample (empty when read from a file written
  /// before them).
  std::vector<double> work_damper, work_friction, work_motor, work_drive, work_impacts;
  std::size_t size() const { return time.size(); }
};

// AxisRole, InitialSpinAxis, LocateSpinAxis and the flip rule: flip_rule.h.

/// Stability of one stage.
struct StageReport {
  int index = 0;
  std::string name;
  std::string law;  ///< "hold" or the law's name.
  double t_begin = 0.0;
  double t_end = 0.0;
  bool rigid = false;                           ///< J constant and h_rel = 0 over the stage.
  math::Vec3 moments_end = math::Vec3::Zero();  ///< Principal moments at the stage end [kg m^2].
  analysis::AxisRole spin_axis_end =
      analysis::AxisRole::kDegenerate;  ///< Role of the spin axis in J at the stage end.
  /// Rigid stages: the analytic regime (FreeBodySolution) of the state at the stage's
  /// start: for the first stage the given initial state itself (bit for bit, so the
  /// analysis does not depend on the method), later the integrated state there.
  std::string regime;
  double one_minus_k2 = 0.0;  ///< Rigid stages: complementary parameter (0 on the separatrix).
  /// (D - I2)/(I3 - I1) of the torque-free motion with J_B and H_B at the stage end
  /// (analysis::SeparatrixDistance, the sweep's rule): 0 on the separatrix, < 0 minor-axis
  /// side.
  double separatrix_distance = 0.0;
  double predicted_flip_half_period = 0.0;  ///< [s] rigid stages; +inf when no flips.
  std::vector<double> predicted_flips;      ///< [s] analytic flip times within the stage.
  std::vector<double> observed_flips;       ///< [s] located by the integrator within the stage.
  double max_flip_time_difference = 0.0;    ///< [s] |observed - predicted| where both exist.
  /// What the stage's stability verdict assumes (RigidBodyCaveat): e.g. that a minor-axis
  /// spin is stable only for a perfectly rigid body.
  std::string caveat;
  /// True when the verdict about the spin axis holds only without energy dissipation
  /// (a minor-axis spin; a dissipative stage, where the spin drifts to the major axis).
  bool rigid_body_only = false;
};

/// The closed-form part of a rigid stage's report: regime, 1 - k^2, the predicted flips
/// of the stage [t_begin, t_end] (when the spin axis is the intermediate axis of J_B) from
/// the state (H_B, q_NB) at its start, and the largest distance of report.observed_flips
/// from them. J_B: the stage's constant inertia.
void SetRigidPrediction(StageReport& report,
                        const math::Mat3& J_B,
                        const math::Vec3& H_B,
                        const math::Quat& q_NB,
                        const math::Vec3& spin_axis_B);

/// The caveat of a stage's verdict: which of its conclusions hold only for a perfectly
/// rigid body (docs/design.md 2.7, the major-axis rule), from the spin axis's role at the stage
/// end. `dissipative`: energy is dissipated continuously in the stage (a damper or friction
/// on a free hinge; a latch's loss is a single impulse, not a drift).
/// Sets report.caveat and report.rigid_body_only.
void SetRigidBodyCaveat(StageReport& report, bool dissipative);

/// A time interval in which the spin is about the intermediate axis (flips possible).
struct DangerWindow {
  double t_begin = 0.0;
  double t_end = 0.0;
};

struct MissionResult {
  /// The compiled run this result came from (its profile, model and estimate).
  std::shared_ptr<const CompiledRun> run;
  const schedule::Profile& profile() const { return run->profile(); }
  Trajectory trajectory;
  std::vector<double> flip_times;  ///< [s] located flips: sign changes of H_B along the
                                   ///< spin axis while it is the intermediate axis.
  math::Vec3 spin_axis_B = math::Vec3::Zero();  ///< InitialSpinAxis of the run.
  std::vector<StageReport> stages;
  std::vector<DangerWindow> danger_windows;
  integrators::Statistics stats;
  integrators::Termination termination = integrators::Termination::kReachedEnd;
  std::string message;
  double max_h_N_drift = 0.0;  ///< max |h_N(t) - h_N(0)| / |h_N(0)| over the output grid.
  double wall_seconds = 0.0;
  /// Hinge profiles: releases, latches, stops, jams in time order (hinge_events.h).
  std::vector<HingeEvent> hinge_events;
  /// Hinge profiles: per panel, the time of its latch (or jam, or coming to rest on a
  /// stop) [s]; NaN if it never locked.
  std::vector<double> latch_times;
  /// [s] times at which the angle between the spin axis and h_N first exceeds 45 degrees
  /// and every later crossing of 45 degrees (both directions), located on the dense output.
  std::vector<double> spin_axis_45_crossings;
  /// The state at the end of the run (t_end, or where the integration stopped), J_B
  /// there (left limit) and the total energy T + V at the start and the end [J].
  integrators::State final_state;
  math::Mat3 final_J_B = math::Mat3::Zero();
  double energy_initial = 0.0;
  double energy_final = 0.0;
  WorkLedger work;  ///< at the end: energy_final = energy_initial + work.sum()
  /// [rad] the largest angle between the spin axis and h_N over the run,
  /// located exactly (run_recorder.h).
  double max_spin_axis_angle = 0.0;
  /// The last output sample of the run (one entry per array; empty without samples).
  Trajectory last_sample;
  /// The outcome measured from the motion, with the predictions (motion_outcome.h).
  /// Outcome-only runs (no samples) have no nutation envelope (trend.valid false).
  analysis::MotionOutcome outcome;
};

/// Options of a mission run.
struct RunOptions {
  /// false: the outcome-only run of a sweep case: no output samples (the sink receives
  /// nothing; danger windows are not computed, max_h_N_drift is the end's) and no stage
  /// reports; the outcome's nutation envelope is then made of the largest nutation inside
  /// the accepted steps (run_recorder.h) instead of the samples'. The rest (flips, 45-degree
  /// crossings, events, the largest spin-axis angle, the final state) is the full run's.
  bool sample_trajectory = true;
  /// Hinge profiles: events (latches, stops, jams, flips, 45-degree crossings) located on
  /// the dense output and finished on partial steps (true), or on the dense output alone
  /// (false: event times within ~1e-12 s, about 100 fewer evaluations per event; for
  /// sweeps).
  bool refine_events = true;
  /// The body axis that flips and angles are measured from (default: InitialSpinAxis).
  std::optional<math::Vec3> spin_axis_B;
};

/// Receives the trajectory of a run as it is computed, in blocks of consecutive samples
/// (kSampleBlock samples, the last block fewer), so that memory stays bounded whatever
/// the horizon (io::TrajectoryFileWriter writes them to a file).
class SampleSink {
 public:
  virtual ~SampleSink() = default;
  /// The next samples, in time order (block.size() >= 1; hinge_angles as in Trajectory).
  virtual void Append(const Trajectory& block) = 0;
};

/// A sink that keeps nothing (a run read for its tables or outcome, not its samples).
class NullSink final : public SampleSink {
 public:
  void Append(const Trajectory& /*block*/) override {}
};

/// Samples per block passed to a SampleSink.
inline constexpr std::size_t kSampleBlock = 4096;

/// Runs the compiled run (the one run loop, run_loop.h, with the body of its profile:
/// StageBody or HingeBody), streaming the trajectory to `sink` (the result's trajectory stays
/// empty; everything else, which needs no stored trajectory, is filled: flips, stage
/// reports, danger windows, max_h_N_drift). Memory does not grow with the number of
/// samples: the output times are computed on demand, and one block is held. Progress (fraction done
/// in [0, 1]) is reported through `progress` if given. Exceptions from the sink pass through
/// (the run stops).
MissionResult RunMission(const CompiledRun& run,
                         SampleSink& sink,
                         const std::function<void(double)>& progress = {},
                         const RunOptions& options = {});

/// RunMission of a profile: compiled (CompiledRun::Compile: throws std::invalid_argument
/// for an invalid profile), then run.
MissionResult RunMission(const schedule::Profile& profile,
                         SampleSink& sink,
                         const std::function<void(double)>& progress = {},
                         const RunOptions& options = {});

/// The initial momentum H_B(t0) of a profile: initial.H_B as given, or J_B w + h_rel_B
/// from initial.w_NB_B, with the inertia sample s0 at t0.
math::Vec3 InitialMomentum(const schedule::Profile& profile, const dynamics::InertiaSample& s0);

/// The initial state of a run: t0, the validated unit attitude, InitialMomentum. Throws
/// std::invalid_argument (naming the profile) for a non-unit attitude or zero momentum.
integrators::State InitialState(const schedule::Profile& profile,
                                const dynamics::InertiaSource& source);

/// The integrator settings of a profile's `integrator:` section.
integrators::IntegratorSettings SettingsOf(const schedule::Profile& profile);

/// The same run with the trajectory collected in the result (by a sink that appends).
MissionResult RunMission(const schedule::Profile& profile,
                         const std::function<void(double)>& progress = {});

/// 3-1-3 Euler angles (precession, nutation, spin) [rad] of B relative to a frame N'
/// whose third axis is h_N/|h_N| (seed appendix A.1). Nutation in [0, pi] is the angle
/// between body axis 3 ... see mission.cc; the singular cases (nutation near 0 or pi)
/// put the whole rotation about the third axis into the precession.
math::Vec3 Euler313RelativeToMomentum(const math::Quat& q_NB, const math::Vec3& h_N);

}  // namespace deploysim::run
