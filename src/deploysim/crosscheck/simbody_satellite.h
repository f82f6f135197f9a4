#pragma once

/// The satellite as a Simbody multibody system (docs/design.md 3), built from the same
/// model::Model structs as the reduced model, and run on an output grid.
///
/// Bodies. Ground is the inertial frame N. The hub is a MobilizedBody::Free on Ground
/// whose body frame is B (origin at B's origin, mass properties: m_h, CoM c_h, inertia
/// about c_h shifted to the origin). Panel k is a MobilizedBody::Pin on its parent's body
/// (the hub, or the parent panel: panel trees, model.h): its body frame P_k has its origin
/// at its hinge point and the axes of its parent's frame at hinge angle 0 (so the axes of
/// B when every angle is 0); the pin's F frame (on the parent, at p_k, which is given from
/// the parent's origin in its axes) and M frame (on the panel, at its origin) are both
/// rotated so that their common Z axis is a_k. The pin coordinate q is then the hinge
/// angle theta_k and R_Bk = R_B,parent(k) Rot(a_k, theta_k), the panel's CoM
/// o_k + R_Bk r_k, exactly as model::ComputeMassProperties assumes. Parents are built
/// before their children; pins (and hinge angles) stay in panel order. No gravity, no
/// other forces.
/// A tensor-mode profile (or a tensors model) is one Free body of mass 1 kg (the mass is
/// irrelevant to the rotation) with its inertia J_B about its CoM at B's origin; its
/// inertia must be constant over the run (Simbody fixes mass properties at
/// realizeTopology).
///
/// Hinge drives. Prescribed: each pin carries a Motion::Custom at position level whose
/// q(t), qdot(t), qddot(t) are the schedule's HingeAngles/Rates/Accelerations (so they
/// are consistent with the law). Stage boundaries are restart points: the integrator stops
/// there, the hinge angles and rates are re-prescribed from the right and the hub velocity
/// is refitted to the momentum just before (a no-op for C1 laws; for the linear law it is
/// the hub's response to the rate jump, as in the reduced model where H_B is continuous).
/// Spring: the pins are free and driven by Force::MobilityLinearSpring and
/// MobilityLinearDamper, latched at the open angle by a MobilityLinearStop (in a tree each
/// acts between a panel and its parent, on the panel's own hinge angle).
///
/// Initial state. Hub attitude R_NB(t0) from the profile; hinge angles and rates at t0;
/// the hub's six generalized speeds solved (a 6x6 linear system: the system momentum is
/// affine in them) so that the system's central angular momentum in N equals
/// R_NB(t0) H_B(t0) and its linear momentum is zero.
///
/// Integration: SimTK::RungeKuttaMersonIntegrator at the requested accuracy, stepping
/// exactly to every output time (no interpolated reports).
///
/// Sampled quantities, frame by frame: R_NB = hub rotation in Ground, w_NB_B = R_NB^T times
/// the hub's angular velocity in Ground, h_N = the system's central angular momentum
/// (calcSystemCentralMomentum) in Ground, H_B = R_NB^T h_N.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "deploysim/math/types.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::crosscheck {

/// Samples of a Simbody run; one entry per output time.
struct SimbodyTrajectory {
  std::vector<double> time;                   ///< [s]
  std::vector<math::Vec3> H_B;                ///< [kg m^2/s] central momentum, B components.
  std::vector<math::Vec3> h_N;                ///< [kg m^2/s] central momentum, N components.
  std::vector<math::Vec3> w_NB_B;             ///< [rad/s] hub angular velocity, B components.
  std::vector<math::Quat> q_NB;               ///< hub attitude (unit).
  std::vector<Eigen::VectorXd> hinge_angles;  ///< [rad] per panel (empty rows for one body).
  std::vector<Eigen::VectorXd> hinge_rates;   ///< [rad/s] per panel.
  /// [J] total kinetic energy about the system CoM (calcKineticEnergy less the CoM's
  /// translation).
  std::vector<double> kinetic_energy;
  std::size_t size() const { return time.size(); }
};

struct SimbodyStatistics {
  long steps = 0;             ///< Accepted steps (main run).
  long attempts = 0;          ///< Attempted steps (main run).
  long realizations = 0;      ///< State realizations (main run).
  long restarts = 0;          ///< Integrator restarts at stage boundaries.
  double wall_seconds = 0.0;  ///< Main run and flip location.
};

/// Hinge-angle history recorded at every accepted Simbody step (spring drive); the
/// reduced model replays it (hinge_history.h).
struct HingeHistory {
  std::vector<double> time;                   ///< [s] ascending, strictly.
  std::vector<Eigen::VectorXd> angle;         ///< [rad] theta per panel.
  std::vector<Eigen::VectorXd> rate;          ///< [rad/s] theta'.
  std::vector<Eigen::VectorXd> acceleration;  ///< [rad/s^2] theta''.
  std::size_t size() const { return time.size(); }
};

struct SimbodyRun {
  SimbodyTrajectory trajectory;
  /// [s] Dzhanibekov flips: sign changes of H_B along the spin axis while it is the
  /// intermediate principal axis of J_B(t) (as run::RunMission counts them), each
  /// located to ~1e-12 s by root finding on restarted integrations (toms748).
  std::vector<double> flip_times;
  /// Simbody's own momentum conservation: max |h_N(t) - h_N(t0)| / |h_N(t0)| over the grid.
  double max_momentum_drift = 0.0;
  double accuracy = 0.0;
  SimbodyStatistics stats;
  HingeHistory history;  ///< Filled by the spring drive only.
};

struct SimbodyOptions {
  double accuracy = 1e-12;  ///< RungeKuttaMersonIntegrator::setAccuracy, > 0.
  /// Locate flips on the Simbody trajectory (needs the spin axis).
  bool locate_flips = true;
};

/// Torsional spring, damper and latch at every hinge (docs/design.md 3): released at
/// rest from the profile's first configuration at t0, each hinge is driven towards its
/// angle in `open` and stopped there by a stiff stop; the spring's neutral angle lies
/// `overtravel` beyond the open angle, so the spring keeps the panel pressed on the stop
/// (a latch). Units: SI, angles in rad.
struct SpringDrive {
  std::string open;               ///< Configuration whose hinge angles are the stop (latch) angles.
  double stiffness = 0.0;         ///< [N m/rad] spring, > 0.
  double overtravel = 0.0;        ///< [rad] > 0: spring neutral angle beyond the open angle.
  double damping = 0.0;           ///< [N m s/rad] hinge damper, >= 0.
  double stop_stiffness = 0.0;    ///< [N m/rad] latch stop stiffness, > 0.
  double stop_dissipation = 0.0;  ///< [s/rad] Hunt-Crossley-like stop dissipation, >= 0.
};

/// H_B(t0) as the reduced model starts (run::RunMission with exact coupling): the
/// profile's initial momentum, or J_B(t0) w + h_rel_B(t0) from its angular velocity.
math::Vec3 InitialMomentum(const schedule::Profile& profile);

/// Runs the Simbody model with the hinges prescribed by the profile's schedule (geometry
/// mode) or as one rigid body (tensor mode, constant inertia), sampling at `grid`
/// (ascending, within [t_begin, t_end] of the profile, first = t_begin). `spin_axis_B`:
/// the body spin axis for flip location (analysis::InitialSpinAxis). Throws
/// std::invalid_argument for a profile Simbody cannot represent (tensor mode with
/// changing inertia) or bad options, std::runtime_error if Simbody fails.
SimbodyRun RunSimbodyPrescribed(const schedule::Profile& profile,
                                const std::vector<double>& grid,
                                const math::Vec3& spin_axis_B,
                                const SimbodyOptions& options);

/// Runs the Simbody model of a hinged profile (geometry mode) with spring-driven hinges
/// from t_begin to t_end of the profile (its stages only fix the start configuration and
/// the horizon), sampling at `grid` and recording the hinge history at every step.
SimbodyRun RunSimbodySpring(const schedule::Profile& profile,
                            const SpringDrive& drive,
                            const std::vector<double>& grid,
                            const math::Vec3& spin_axis_B,
                            const SimbodyOptions& options);

}  // namespace deploysim::crosscheck
