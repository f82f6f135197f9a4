#pragma once

/// The motion and the drive of single hinges of a hinge profile (hinge_plan.h):
/// prescribed angles along a hinge's moves, the generalized force of a free hinge's
/// drive and its stored energy.

#include <vector>

#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/schedule/hinge_plan.h"

namespace deploysim::schedule {

/// Angle [rad], rate [rad/s] and acceleration [rad/s^2] of a hinge at one time.
struct HingeKinematics {
  double angle = 0.0;
  double rate = 0.0;
  double acceleration = 0.0;
};

/// A prescribed hinge: its moves from its angle at the run's start. Between and before
/// the moves it holds its angle; after the last one it holds the last angle. A kTo move
/// goes from the angle at its t_begin to its target along its law (theta = theta_b + s(tau)
/// (target - theta_b), tau = (t - t_begin) / (t_end - t_begin)); a kRate move turns at
/// its rate. At a window boundary Side::kLeft takes the motion before it and
/// Side::kRight the motion after it.
class PrescribedHinge {
 public:
  PrescribedHinge() = default;
  /// `moves` ascending and not overlapping (ValidateProfile checks it).
  PrescribedHinge(std::vector<HingeMove> moves, double initial_angle);
  HingeKinematics At(double t, dynamics::Side side = dynamics::Side::kRight) const;
  /// Window boundaries strictly inside (t0, t1), ascending.
  std::vector<double> Breakpoints(double t0, double t1) const;
  /// The first window boundary after t (+inf if none).
  double NextBreakpoint(double t) const;
  /// True when the hinge does not move anywhere in (t0, t1).
  bool IsAtRestOn(double t0, double t1) const;

 private:
  /// The first move that ends after t (moves ascend: a binary search).
  std::vector<HingeMove>::const_iterator FirstNotOver(double t) const;

  std::vector<HingeMove> moves_;
  std::vector<double> start_angles_;  // angle at each move's t_begin
  double end_angle_ = 0.0;            // after the last move
};

/// The generalized force of a free hinge's drive Q(theta, theta') [N m] (hinge_plan.h):
/// spring, damper, motor and friction (not the stops or the latch, which act by impulses).
/// `slip`: the direction (+1, -1) a hinge with exact Coulomb friction slides in over the
/// segment being integrated (its friction is -torque slip, constant until the rate reaches
/// 0, an event); 0: none (a hinge at rest, whose holding torque is asked for: the sign of
/// a rate that is 0 up to rounding means nothing). Unused by the regularized law.
double DriveTorque(const FreeDrive& drive, double theta, double theta_dot, int slip = 0);

/// The torque of a servo motor (Motor::Kind::kServo) at hinge angle theta and rate
/// theta_dot with the planned motion `ref` at that time [N m] (0 for other motors). Not part
/// of DriveTorque (it depends on time); counted as non-conservative in the energy balance.
double ServoTorque(const Motor& motor, const HingeKinematics& ref, double theta, double theta_dot);

/// The part of DriveTorque that dissipates or supplies energy, i.e. all but the spring:
/// dE/dt = sum_k NonConservativeTorque_k theta'_k along the flow (E = T + V).
double NonConservativeTorque(const FreeDrive& drive, double theta_dot, int slip = 0);

/// NonConservativeTorque by its source [N m] (their sum), for the energy ledger.
struct NonConservativeParts {
  double damper = 0.0;
  double friction = 0.0;
  double motor = 0.0;  ///< a servo's torque is added by the caller (ServoTorque)
};
NonConservativeParts NonConservativeTorqueParts(const FreeDrive& drive,
                                                double theta_dot,
                                                int slip = 0);

/// Friction::coulomb(): exact Coulomb friction (sticks and slips), not the regularized law.
inline bool IsCoulomb(const Friction& f) { return f.torque > 0.0 && f.regularization_speed == 0.0; }

/// The spring's stored energy V(theta) = 1/2 k (theta - rest)^2 - preload (theta - rest) [J].
double SpringEnergy(const FreeDrive& drive, double theta);

}  // namespace deploysim::schedule
