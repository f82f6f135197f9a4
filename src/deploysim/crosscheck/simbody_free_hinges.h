#pragma once

/// An independent Simbody model of free hinges (docs/design.md 2.7 and 3): the
/// reference against which the reduced free-hinge model is verified. It is built from the
/// same structs (model::Model, a hinge profile's schedule::HingePlan per panel) but uses
/// none of the reduced model's dynamics: Simbody integrates the multibody system, and the
/// events (latch, jam, stop, rest, release) are applied here with Simbody's own mass
/// matrix (SimbodyMatterSubsystem::calcM).
///
/// Bodies. Ground is the inertial frame N. The hub is a MobilizedBody::Free on Ground whose
/// body frame is B; panel k is a MobilizedBody::Pin on its parent (the hub, or panel
/// Panel::parent) whose body frame has its origin at the hinge point and the parent's axes
/// at theta_k = 0; the pin's F frame (on the parent, at p_k) and M frame (on the panel, at
/// its origin) are rotated so that their common Z axis is a_k (model.h conventions). The
/// pin coordinate q is theta_k, its speed u is theta'_k. No gravity.
///
/// Hinges by schedule::HingePlan::Kind:
///  - locked: the pin is locked (MobilizedBody::lock at position level) at its initial angle;
///  - prescribed: a Motion::Custom at position level gives theta, theta', theta'' from the
///    HingeMove windows (kTo: schedule::EvaluateLaw from the angle at the window's start;
///    kRate: constant rate; held between windows); window ends are restart points;
///  - free: locked until released (at the start, at a time, or `delay` after another
///    panel's latch), then driven by Q = -k (theta - rest) + preload - c theta' + motor -
///    mu tanh(theta'/omega_f): Force::MobilityLinearSpring and MobilityLinearDamper for the
///    spring and damper, one Force::Custom for preload, motor and friction (its potential
///    energy is -preload (theta - rest), so Simbody's potential energy is the spring's
///    stored energy of schedule/hinge_plan.h).
///
/// Velocity jumps (latch, jam, stop, rest, and the restarts at prescribed window ends
/// where a prescribed rate may jump). The generalized impulse of a torque pair at hinge k
/// is lambda e_k: with Simbody's mass matrix M (calcM, all mobilities: the hub's 6, then the
/// pins), the new speeds keep the generalized momenta (M u) of every free mobility (the
/// hub's six and the free, unlocked hinges) and give the constrained ones (locked,
/// prescribed, and the event's hinge) their new rates; lambda = (M (u+ - u-))_k [N m s].
/// A latch (or jam) sets theta'_k+ = 0, then locks the pin; a stop sets theta'_k+ =
/// -e theta'_k-; a rebound slower than schedule::kRestSpeed is a rest: theta'_k+ = 0 and the
/// pin is locked for the rest of the run. The energy dissipated is the work of the
/// impulse, -lambda (theta'_k- + theta'_k+) / 2 = (M^-1)_kk lambda^2 / 2 for a latch: the
/// kinetic energy lost, unless a prescribed hinge is moving (its drive then does impulsive
/// work as well).
///
/// Event location. Every witness (latch: d (theta - latch) with d the direction from the
/// release angle to the latch; jam: the same at the jam angle; stops: theta - max,
/// min - theta) is checked at every accepted Simbody step; a sign change is located by
/// Brent-like root finding (toms748) on integrations restarted from the step's start at
/// the same accuracy, to kEventTimeTolerance; the event is applied at the bracket's end
/// where the witness has crossed, and Simbody is restarted there. Simultaneous events
/// (e.g. two symmetric wings latching) are applied one after the other at the same time.
/// After a rebound the step size is limited to an eighth of the predicted bounce so that
/// the next impact is not stepped over.
///
/// Initial state. Hub attitude from the profile; hinge angles of the profile's initial
/// configuration; prescribed rates from the windows (from the right), free and locked
/// rates 0; the hub's speeds fitted so that the system's linear momentum is zero and either
/// the hub's angular velocity is the profile's w_NB_B or the system's central angular
/// momentum is R_NB H_B (whichever the profile gives).
///
/// Samples at the output grid (after any restart or event at a grid time): H_B, h_N
/// (calcSystemCentralMomentum), w_NB_B, q_NB, hinge angles and rates, the kinetic energy
/// about the system CoM, the stored (potential) energy and their sum, and J_B (the system's
/// central inertia in B). Flips follow analysis/flip_rule.h; the spin-axis crossings are
/// the times at which the angle between the body spin axis (R_NB spin_axis_B) and h_N
/// crosses given angles; both are located like the events (to kEventTimeTolerance).

#include <Eigen/Core>
#include <vector>

#include "deploysim/run/hinge_events.h"
#include "deploysim/crosscheck/simbody_satellite.h"
#include "deploysim/math/types.h"
#include "deploysim/model/model.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::crosscheck {

/// Events and crossings are located to this bracket width [s] (relative to max(1, |t|)).
inline constexpr double kEventTimeTolerance = 1e-13;

/// A compliant latch in place of the plastic one (the check that a stiff stop converges to
/// the plastic latch): when theta_k reaches the latch angle, a
/// two-sided Simbody Force::MobilityLinearStop (both bounds at the latch angle, stiffness
/// `stiffness`, no Hunt-Crossley dissipation) and a Force::MobilityLinearDamper of damping
/// ratio `damping_ratio` about the hinge's effective inertia 1 / (M^-1)_kk engage; no
/// impulse is applied and the pin stays free. The latch event is recorded (impulse 0) and
/// releases that wait for it are scheduled; the hinge's jam and stop witnesses are off
/// from then on.
struct CompliantLatch {
  double stiffness = 0.0;      ///< [N m/rad] 0: the plastic latch (impulse, then lock).
  double damping_ratio = 1.0;  ///< > 0 (1: critical).
};

struct SimbodyFreeHingeOptions {
  double accuracy = 1e-14;   ///< RungeKuttaMersonIntegrator::setAccuracy, in (0, 1).
  bool locate_flips = true;  ///< Locate flips (analysis/flip_rule.h) on the trajectory.
  /// [rad] angles in (0, pi) whose crossings by the angle between the body spin axis and
  /// h_N are located (e.g. pi/4 for the major-axis demonstration).
  std::vector<double> spin_axis_angles;
  CompliantLatch compliant_latch;  ///< Default: plastic latches.
};

/// One crossing of a requested angle by the angle between the body spin axis and h_N.
struct SpinAxisCrossing {
  double angle = 0.0;       ///< [rad] the requested angle.
  double t = 0.0;           ///< [s]
  bool increasing = false;  ///< The spin axis moves away from h_N through `angle`.
};

struct SimbodyFreeHingeStatistics {
  long steps = 0;         ///< Accepted Simbody steps (main integration).
  long attempts = 0;      ///< Attempted steps (main integration).
  long realizations = 0;  ///< State realizations (main integration).
  long restarts = 0;      ///< Integrator restarts (events, releases, window ends).
  /// Restarted integrations made to locate events, flips and crossings.
  long location_integrations = 0;
  double wall_seconds = 0.0;  ///< Whole run.
};

struct SimbodyFreeHingeRun {
  /// Samples at the grid: time, H_B, h_N, w_NB_B, q_NB, hinge angles and rates, kinetic
  /// energy about the system CoM.
  SimbodyTrajectory trajectory;
  std::vector<double> stored_energy;  ///< [J] Simbody's potential energy (springs, preloads,
                                      ///< engaged compliant latches).
  std::vector<double> total_energy;   ///< [J] kinetic (about the CoM) + stored.
  std::vector<math::Mat3> J_B;        ///< [kg m^2] system inertia about its CoM, B axes.
  /// Events in time order (releases at the start included, at t_begin).
  std::vector<run::HingeEvent> events;
  std::vector<Eigen::VectorXd> event_hinge_angles;  ///< [rad] every hinge angle at each event.
  /// Per event: which hinges were free (released, unlocked, not prescribed) just before it.
  std::vector<std::vector<bool>> event_free_hinges;
  std::vector<double> latch_times;  ///< [s] per panel: its latch (NaN if it never latched).
  std::vector<double> flip_times;   ///< [s] (if options.locate_flips).
  std::vector<SpinAxisCrossing> spin_axis_crossings;  ///< In time order.
  /// Simbody's own momentum conservation: max |h_N(t) - h_N(t0)| / |h_N(t0)| over the grid.
  double max_momentum_drift = 0.0;
  double accuracy = 0.0;
  SimbodyFreeHingeStatistics stats;
};

/// Runs the Simbody model of a hinge profile (profile.is_hinge_profile(), a hinged model)
/// from t_begin, sampling at `grid` (ascending, first = t_begin, last <= t_end).
/// `spin_axis_B`: the body spin axis for flips and spin-axis crossings (unit, B; e.g.
/// analysis::InitialSpinAxis). Throws std::invalid_argument for a profile it cannot run
/// (not a hinge profile, not hinged, plans not one per panel, a parent that is not a tree)
/// or bad options; std::runtime_error if Simbody fails.
SimbodyFreeHingeRun RunSimbodyFreeHinges(const schedule::Profile& profile,
                                         const std::vector<double>& grid,
                                         const math::Vec3& spin_axis_B,
                                         const SimbodyFreeHingeOptions& options);

/// Simbody's mass matrix (calcM) of the hinged body at `hinge_angles` [rad] with the hub at
/// rest at B = N: mobilities in the order hub angular velocity (3, B = N axes), hub
/// linear velocity (3), then the hinges in panel order ((6 + n) x (6 + n), SI units). For
/// tests: (M^-1)_kk restricted to a set of free mobilities is the effective inverse
/// inertia of a latch at hinge k.
Eigen::MatrixXd SimbodyMassMatrix(const model::HingedBody& body,
                                  const Eigen::VectorXd& hinge_angles);

}  // namespace deploysim::crosscheck
