#pragma once

/// Up-front estimate of the work a profile asks for, and the run limits checked from it
/// (CompiledRun::Compile calls CheckWork, so simulate, analyze, crosscheck and every
/// sweep case are refused before they start). A torque-free run's cost grows with the
/// number of turns of the body: every integrator resolves the rotation (or, for the
/// Lie-group and exact methods, the motion of H_B in the body, which is no faster), and
/// the flips of a stage (FreeBodySolution::FlipTimes) number at most two per turn.
///
/// Rate bound per stage: |H_B| = M is the same at every time of a torque-free run, and
/// |w_NB_B| = |J_B^-1 (H_B - h_rel_B)| <= M / I_min, I_min the smallest principal moment
/// of J_B. First stage (a hold; the initial state is known): the largest |w| on that
/// state's energy ellipsoid (exact for a rigid body). Later holds: M / I_min of the held
/// configuration. Moves: tensor mode, the smaller I_min of the two end tensors (J_B is a
/// convex combination of them); geometry mode, the sum of the parts' own smallest
/// moments (a lower bound of I_min at any hinge angles). The panels' relative momentum
/// h_rel_B is left out (it turns the hub by about the hinge travel: a fraction of a turn).
/// Cost: a principal decomposition per configuration used (~1 us each); no schedule is
/// built when initial.H_B is given (as in every sweep case).
///
/// Hinge profiles: one entry for the whole run, the hub's rate bounded as for a
/// geometry-mode move plus, per hinge, what it can turn (a prescribed rate; a free hinge's
/// spring frequency sqrt(k / I_min), a constant motor's |tau| D / I_min, a torque-speed
/// motor's no-load speed; I_min its panel's smallest moment).

#include <cstdint>
#include <string>
#include <vector>

#include "deploysim/schedule/profile.h"

namespace deploysim::schedule {
class DeploymentSchedule;
}  // namespace deploysim::schedule

namespace deploysim::analysis {

/// Largest number of turns of the body (sum over the stages of max |w| * duration / 2 pi)
/// a run may ask for. 1e6 turns are 69 days at 10 rpm; they keep the flips of any stage
/// (<= 2 per turn, +1) 5x below FreeBodySolution::kMaxFlips and the steps of `exact`
/// (8 per period) below the integrator's max_steps.
inline constexpr double kMaxTurns = 1e6;
/// Largest number of steps of a fixed-step method (sum over the stages of
/// ceil(duration / integrator.step)): the integrator's max_steps
/// (integrators::IntegratorSettings), where it would stop anyway.
inline constexpr double kMaxFixedSteps = 5e7;

struct StageWork {
  double duration = 0.0;     ///< [s]
  double max_rate = 0.0;     ///< Bound on |w_NB_B| [rad/s] (see the file comment).
  double turns = 0.0;        ///< max_rate * duration / (2 pi).
  double fixed_steps = 0.0;  ///< ceil(duration / integrator.step) for fixed-step methods, else 0.
};

struct WorkEstimate {
  std::vector<StageWork> stages;  ///< One per profile stage.
  double momentum = 0.0;          ///< M = |H_B(t0)| [kg m^2/s].
  double turns = 0.0;             ///< Sum over the stages.
  double fixed_steps = 0.0;       ///< Sum over the stages (0 for adaptive methods).
  bool finite = true;             ///< False if a rate is not finite (an overflow).
  /// Hinge profiles: the stiffest rate [rad/s] of the free hinges' motion linearized at
  /// the start: the largest of sqrt(lambda) over the generalized eigenvalues lambda of
  /// (K, S) plus the largest of (C, S), with S the free hinges' mass matrix with the hub
  /// free (the Schur complement of J_B in M, docs/design.md 2.7), K their spring and servo
  /// stiffnesses plus the centrifugal stiffness of the spin (|w|^2 times S's diagonal: a
  /// panel on a spinning hub swings at about the spin rate), and C their dampers, servo
  /// damping and the regularized friction's slope (torque / regularization speed). 0
  /// without free hinges.
  double hinge_rate = 0.0;
  /// The time the free hinges are estimated to move [s] (from each release to its latch,
  /// estimated as half a period of its stiffest rate, or to the end).
  double free_time = 0.0;
  /// The accepted steps the run is estimated to take (EstimateSteps); the step-size
  /// bound it implies is the run's duration over it.
  double steps = 0.0;
  /// The estimated wall time on one core [s]: steps times the cost of a step, which grows
  /// with the panels (the tree's kinematics) and the cube of the free hinges (the mass
  /// matrix's solve).
  double seconds = 0.0;
};

/// The longest run accepted: its estimated wall time on one core [s]. Beyond it the run
/// is refused before it starts, with the estimate and what to change.
inline constexpr double kMaxRunSeconds = 3600.0;
/// Runs estimated above this [s] print their estimate before they start, and show
/// progress.
inline constexpr double kLongRunSeconds = 60.0;

/// One line for a long run: "estimated N steps (stiffest hinge rate R rad/s over F s ...),
/// about S s on one core".
std::string DescribeWork(const WorkEstimate& e);

/// The estimate for a valid profile (schedule::ValidateProfile passed; the integrator
/// method known). `schedule`: the stage profile's schedule when the caller has it (else
/// one is built when initial.H_B is not given). Throws only what DeploymentSchedule throws.
WorkEstimate EstimateWork(const schedule::Profile& profile,
                          const schedule::DeploymentSchedule* schedule = nullptr);

/// How many times EstimateWork has run in this process (a compiled run estimates once:
/// tests count it).
std::uint64_t WorkEstimateCount();

/// The limits kMaxTurns, kMaxFixedSteps and kMaxRunSeconds on the estimate `e` of
/// `profile`: throws std::invalid_argument "<profile source>: <what>: <numbers> (rule:
/// ...)", one line. An estimate that is not finite (a value in the profile whose square or
/// product overflows) is refused.
void CheckWork(const schedule::Profile& profile, const WorkEstimate& e);

}  // namespace deploysim::analysis
