#pragma once

/// How each hinge moves in a `hinges:` profile (docs/design.md 2.7): locked at its
/// initial angle, prescribed along laws on its own time windows, or free — driven by the
/// dynamics with a spring, damper, motor and friction, caught by stops and a latch,
/// released at a time or after another panel latches. Plain structs, free of YAML
/// (io_yaml reads them; docs/file_formats.md documents the file). Units: SI (rad, s,
/// N m, N m s/rad); degrees only in the file.
///
/// Sign conventions. theta_k is the panel's hinge angle about its axis a_k (right-hand
/// rule, model.h). A generalized torque Q_k > 0 turns the panel towards increasing
/// theta_k. The free hinge's generalized force (docs/design.md 2.7):
///   Q_k = -k (theta - theta_rest) + preload                       spring
///         - c theta'                                              damper
///         + tau_motor(theta')                                     motor
///         - mu tanh(theta' / omega_f)                             friction (regularized)
/// Stored (potential) energy of the spring: V = 1/2 k (theta - theta_rest)^2
///   - preload (theta - theta_rest), so that Q_spring = -dV/dtheta.

#include <limits>
#include <string>
#include <vector>

#include "deploysim/math/units.h"
#include "deploysim/schedule/laws.h"

namespace deploysim::schedule {

/// One prescribed move of a hinge on its own time window [t_begin, t_end].
struct HingeMove {
  enum class Kind {
    kTo,    ///< From the angle at t_begin to `angle` at t_end along `law` (laws.h).
    kRate,  ///< At the constant rate `rate` over the window (a rotor at a held rate);
            ///< the rate jumps at both ends (breakpoints, like the linear law).
  };
  Kind kind = Kind::kTo;
  double t_begin = 0.0;         ///< [s]
  double t_end = 0.0;           ///< [s] > t_begin. A run may end inside the window.
  double angle = 0.0;           ///< [rad] kTo: the angle at t_end.
  Law law = Law::kMinimumJerk;  ///< kTo: step is not allowed (an impulsive hinge motion).
  double rate = 0.0;            ///< [rad/s] kRate.
};

/// Torsion spring: Q = -stiffness (theta - rest_angle) + preload.
struct Spring {
  double stiffness = 0.0;   ///< [N m/rad] >= 0.
  double rest_angle = 0.0;  ///< [rad] neutral angle.
  double preload = 0.0;     ///< [N m] torque at the rest angle (a constant-torque part).
};

/// Motor torque on the hinge [N m].
struct Motor {
  enum class Kind {
    kNone,
    kConstant,     ///< Q = torque.
    kTorqueSpeed,  ///< Q = stall_torque (1 - theta' / no_load_speed): the DC-motor line; it
                   ///< brakes above the no-load speed. stall_torque and no_load_speed have
                   ///< the same sign (the direction the motor drives).
    kServo,        ///< A position servo following a planned motion:
                   ///< Q = servo_stiffness (theta_ref - theta) + servo_damping (theta'_ref -
                   ///< theta'), theta_ref(t) the `follow` moves from the hinge's angle at the
                   ///< run's start (as a prescribed hinge's; PrescribedHinge). As the gains
                   ///< grow the hinge follows the plan: the free hinge reproduces the
                   ///< prescribed one (error ~ 1 / servo_stiffness).
  };
  Kind kind = Kind::kNone;
  double torque = 0.0;            ///< [N m] kConstant.
  double stall_torque = 0.0;      ///< [N m] kTorqueSpeed, non-zero.
  double no_load_speed = 0.0;     ///< [rad/s] kTorqueSpeed, non-zero, same sign as stall_torque.
  double servo_stiffness = 0.0;   ///< [N m/rad] kServo, > 0.
  double servo_damping = 0.0;     ///< [N m s/rad] kServo, >= 0.
  std::vector<HingeMove> follow;  ///< kServo: the planned moves (ascending, not overlapping).
};

/// Coulomb friction at the hinge, one of two laws:
/// - exact (regularization_speed 0): Q = -torque sign(theta') while the hinge slips; when
///   its rate reaches 0 it sticks if the torque that holds it at rest is at most `torque`,
///   and slips again when that holding torque exceeds `torque` (stick and slip are events,
///   docs/design.md 2.7);
/// - regularized (regularization_speed > 0, a documented choice): Q = -torque tanh(theta' /
///   regularization_speed): far above that speed the Coulomb torque, below it a viscous
///   torque of slope torque / regularization_speed, so a panel held by friction creeps
///   instead of sticking. kMinRegularizationSpeed keeps it affordable.
struct Friction {
  double torque = 0.0;                ///< [N m] >= 0; 0: no friction.
  double regularization_speed = 0.0;  ///< [rad/s]; 0: exact Coulomb friction.
};

/// Hard stops: the hinge cannot pass min_angle or max_angle. At a stop the panel
/// rebounds with coefficient of restitution e (theta'+ = -e theta'-, the impulse of
/// docs/design.md 2.7). A panel pressed on the stop whose rebound is slower than
/// kRestSpeed, would be back within kContactTime, or would leave the stop by no more than
/// the integration's angle tolerance (atol + rtol |angle|) rests on it: the hinge is held
/// there until the torque that holds it pulls it away (a lift-off, docs/design.md 2.7).
struct Stops {
  double min_angle = -std::numeric_limits<double>::infinity();  ///< [rad]; -inf: none.
  double max_angle = std::numeric_limits<double>::infinity();   ///< [rad]; +inf: none.
  double restitution = 0.0;                                     ///< e in [0, 1].
  bool any() const {
    return min_angle > -std::numeric_limits<double>::infinity() ||
           max_angle < std::numeric_limits<double>::infinity();
  }
};

/// Latch: when theta reaches `angle` moving towards it (from the side where the hinge
/// was released), a plastic impulse stops the hinge and it is locked for the rest of the
/// run. Jam (a failure mode: a panel that sticks part-way): the hinge seizes, the same
/// plastic lock, once it has turned `jam_fraction` of the way from its release angle to
/// the latch angle (0 < jam_fraction < 1), before the latch.
struct Latch {
  bool enabled = false;
  double angle = 0.0;         ///< [rad] within the stops.
  double jam_fraction = 0.0;  ///< 0: no jam; in (0, 1): the failure mode above.
};

/// When a free hinge starts to move. Until then it is locked at its initial angle.
struct Release {
  enum class Kind {
    kAtStart,     ///< Free from the run's start.
    kAtTime,      ///< At `time`.
    kAfterLatch,  ///< `delay` after panel `panel` latches (never, if it never latches).
  };
  Kind kind = Kind::kAtStart;
  double time = 0.0;   ///< [s] kAtTime.
  int panel = -1;      ///< kAfterLatch: index of the panel whose latch releases this one.
  double delay = 0.0;  ///< [s] >= 0, kAfterLatch.
};

/// The drive of a free hinge.
struct FreeDrive {
  Spring spring;
  double damping = 0.0;  ///< [N m s/rad] >= 0: Q = -damping theta'.
  Motor motor;
  Friction friction;
  Stops stops;
  Latch latch;
  Release release;
};

/// How one hinge moves over a run.
struct HingePlan {
  enum class Kind {
    kLocked,      ///< At its initial angle for the whole run.
    kPrescribed,  ///< Along `moves` (ascending, not overlapping); locked between them.
    kFree,        ///< Driven by `drive` (docs/design.md 2.7) once released.
  };
  Kind kind = Kind::kLocked;
  std::vector<HingeMove> moves;  ///< kPrescribed.
  FreeDrive drive;               ///< kFree.
};

/// A rebound off a stop slower than this [rad/s] leaves the panel resting on the stop
/// (0.0006 deg/s: 10 um/s at the tip of a 1 m panel). Bounces with restitution e need about
/// ln(kRestSpeed / |theta'|) / ln(e) impacts to get there (e = 0.5 from 1 rad/s: 17).
inline constexpr double kRestSpeed = 1e-5;
/// A rebound off a stop that would be back on a stop within this time [s], or an impact
/// that comes this soon after the hinge's previous one, is no rebound: the contact never
/// opens (a hinge stop's impact itself lasts milliseconds; a latch-up stops a panel in
/// about 10 ms), and the panel rests on the stop. It ends the impacts whose times
/// accumulate (a panel pressed on its stop: the flights shrink as e^n) and a rattle
/// between close stops (restitution 1 between stops 2e-6 deg apart).
inline constexpr double kContactTime = 1e-3;

/// The accepted ranges of a free hinge's drive (docs/file_formats.md, "Accepted ranges"),
/// refused before a run outside them (schedule::ValidateProfile): beyond them a value
/// describes no deployable panel's hardware, and the run's cost cannot be bounded (a
/// spring's rest angle of 1e12 deg stores 1e23 J; the steps follow sqrt(k / I)).
/// Angles: stops, latch and spring rest angles, 10 turns either way [rad].
inline constexpr double kMaxDriveAngleDeg = 3600.0;  ///< the same [deg], as files give it
inline constexpr double kMaxDriveAngle = kMaxDriveAngleDeg * math::kRadiansPerDegree;
/// Spring and servo stiffness [N m/rad].
inline constexpr double kMaxDriveStiffness = 1e9;
/// Damper and servo damping [N m s/rad].
inline constexpr double kMaxDriveDamping = 1e9;
/// Preload, motor, stall and friction torques [N m].
inline constexpr double kMaxDriveTorque = 1e6;
/// A torque-speed motor's no-load speed: 1000 turns/s [rad/s].
inline constexpr double kMaxDriveSpeed = 2000.0 * 3.14159265358979323846;
/// The regularized friction law's smallest speed, 0.01 deg/s [rad/s]: below it the law's
/// viscous slope torque / speed makes the equations stiff (at 1e-6 deg/s a 600 s run did
/// not finish in a minute). Exact Coulomb friction (stick and slip) needs no speed.
inline constexpr double kMinRegularizationSpeed = 0.01 * math::kRadiansPerDegree;

/// "locked", "prescribed", "free".
std::string ToString(HingePlan::Kind kind);

}  // namespace deploysim::schedule
