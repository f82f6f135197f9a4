#pragma once

/// The linear stability of a steady spin, from the same equations the integrator solves
/// (docs/design.md 2.8, "Linear stability of the steady spin").
///
/// A phase of a run is autonomous when nothing in it depends on time (no prescribed hinge
/// moving, unless it turns at a constant rate about its own symmetry axis, as a rotor
/// does). Its reduced state y = (H_B, theta_f, p_f) (the momentum in B, the free hinges'
/// angles and momenta; the attitude drops out) obeys y' = F(y) with
///   H_B' = H_B x w(y),   (theta_f, p_f)' = ShapeSystem::Evaluate(...).
/// A relative equilibrium (a steady spin) is a y* with F(y*) = 0 on the sphere |H_B| = M:
/// the hub spins about H_B with every hinge at rest, except free hinges whose angle is
/// cyclic (a free rotor: nothing depends on its angle, which turns at a steady rate).
/// It is found by Gauss-Newton from the phase's own state (the principal axis nearest
/// H_B, the hinges where they are); the Jacobian dF/dy at y* is formed by central
/// differences of F with one Richardson extrapolation (error O(h^4), h = 1e-4 of each
/// coordinate's scale: ~1e-12 relative), and its eigenvalues are the modes of small
/// motions about the spin. Exact for small nutation, whatever the size of the sink.
///
/// Beside it, the quasi-rigid energy-sink estimate (the textbook argument, e.g. Kaplan
/// 1976 ch. 5, Hughes 1986 ch. 7): the nutation of the body with its sink coordinates
/// held (the rigid nutation mode, frequency w_n, momentum perturbation dH(t)) drives the
/// sink; the sink's mean dissipated power <P> (< 0) drains the energy function
/// E = 1/2 (H_B - h_r)' J_B^-1 (H_B - h_r) (h_r: rotors' momentum, held), whose excess over
/// the steady spin on the momentum sphere is dE = 1/2 dH' (J_B^-1 - mu I) dH (mu = |w*| /
/// |H*|); with dE ~ amplitude^2, the amplitude grows at sigma_qr = <P> / (2 <dE>). For a
/// spin about the minor axis dE < 0 (sigma_qr > 0: the spin drifts to the major axis),
/// about the major axis dE > 0 (the nutation decays). It is first order in the sink's size
/// and ignores how the sink detunes the nutation (see the docs' table).

#include <Eigen/Core>
#include <complex>
#include <functional>
#include <string>
#include <vector>

#include "deploysim/math/types.h"

namespace deploysim::schedule {
class FreeHingeSystem;
}  // namespace deploysim::schedule

namespace deploysim::analysis {

/// The reduced equations of an autonomous phase: y = (H_B, theta_f, p_f) (3 + 2m).
struct ReducedFlow {
  int free = 0;  ///< m, the free hinges
  /// y' = F(y).
  std::function<Eigen::VectorXd(const Eigen::VectorXd& y)> rhs;
  /// F at time tau from the phase's start (empty: F does not depend on time). Where it
  /// does, the steady motion is periodic if F repeats with `period`, and none otherwise.
  std::function<Eigen::VectorXd(double tau, const Eigen::VectorXd& y)> rhs_time;
  /// [s] how long the phase lasts (+inf: to the run's end or beyond): F is probed inside it.
  double phase_length = 0.0;
  /// [s] > 0: a hinge held at a steady rate by its drive turns once in this time (a
  /// motor-held rotor); F that depends on time may repeat with it.
  double period = 0.0;
  /// The power of the sinks (dampers, friction) at y [W] (<= 0); empty: no sink.
  std::function<double(const Eigen::VectorXd& y)> sink_power;
  /// J_B [kg m^2] and the rotors' momentum h_r [kg m^2/s] at y (the quasi-rigid body).
  std::function<void(const Eigen::VectorXd& y, math::Mat3& J_B, math::Vec3& h_r)> rigid;
  /// Free hinges whose angle is cyclic (rotors), in free order; found when empty.
  std::vector<int> cyclic;
  /// Free hinges that can turn without bound (no spring, no stops, no latch: a free
  /// rotor), in free order. One that turns and is not cyclic (a damper rides it) makes
  /// the steady motion periodic: its angle advances 2 pi per period.
  std::vector<int> winding;
  /// Each winding hinge's axis in B (empty: unknown, its axis moves in B).
  std::vector<math::Vec3> winding_axes;
};

/// One mode of small motions about the steady spin.
struct SpinMode {
  std::complex<double> lambda;  ///< [1/s] eigenvalue: growth rate + i frequency
  /// How much of the mode is a tilt of H_B in the body (the nutation): the transverse
  /// momentum perturbation over |H| against the mode's whole (scaled) eigenvector, 0..1.
  double momentum_share = 0.0;
};

/// The steady motion and its linear stability.
struct SteadySpin {
  bool found = false;
  std::string reason;  ///< why there is none (found false)
  /// "steady" (at rest in the hub's frame: a relative equilibrium) or "periodic" (a
  /// periodic orbit in the hub's frame, floquet.h).
  std::string motion;
  double period = 0.0;  ///< [s] periodic: the orbit's period
  Eigen::VectorXd y;    ///< the relative equilibrium (H_B, theta_f, p_f); periodic: y(0)
  math::Vec3 w_B = math::Vec3::Zero();  ///< [rad/s] the hub's spin there
  /// How well y solves the equations: steady, |F(y*)| relative to |H| |w| (cyclic angles
  /// left out); periodic, the return's miss (floquet.h).
  double residual = 0.0;
  /// Every non-zero eigenvalue, largest real part first; periodic: the Floquet exponents
  /// ln(mu) / T (imaginary part modulo 2 pi / T), the multipliers 1 (the flow, |H|) left out.
  std::vector<SpinMode> modes;
  /// Periodic: the direction of H_B along the orbit, at kOrbitPoints equal steps of one
  /// period from y (the nutation is the angle from this closed curve; empty: steady).
  std::vector<math::Vec3> orbit_axes;
  /// The share of the period either side of the phase time (t - phase start) mod period
  /// in which a state's orbit point is sought: 0 for a motion forced in time (the clock
  /// is exact), 1/16 for a free rotor's orbit (the motion's phase settles at an offset).
  double orbit_slack = 0.0;
  /// A free rotor's orbit: the rotor's free-order index (-1: none) and its angle at y with
  /// its advance per period (+-2 pi): the rotor's angle is the orbit's exact clock.
  /// orbit_rotor_panel: its model panel index, filled by the run that knows it (-1: none).
  int orbit_rotor = -1;
  int orbit_rotor_panel = -1;
  double orbit_rotor_angle = 0.0, orbit_rotor_advance = 0.0;
  /// The nutation mode: the mode that tilts H_B with the largest real part (the one the
  /// nutation envelope follows). Its growth rate [1/s] (> 0 unstable) and frequency
  /// [rad/s] (0 for a divergent, non-oscillating mode, as about an intermediate axis).
  double growth_rate = 0.0;
  double frequency = 0.0;
  /// The largest real part of any mode [1/s].
  double max_real = 0.0;
  /// Linear verdict: "asymptotically stable", "neutrally stable" (|Re| at rounding level
  /// for every mode: a rigid or undamped spin about the minor or major axis) or
  /// "unstable".
  std::string verdict;
  /// The quasi-rigid energy-sink estimate of growth_rate [1/s] (NaN: no sink, or no
  /// oscillating rigid nutation mode).
  double quasi_rigid_rate = 0.0;
  /// The rigid nutation frequency with the sinks held [rad/s] (NaN without one).
  double rigid_frequency = 0.0;
};

/// The largest relative residual of a steady or periodic motion that is taken as a
/// solution: beyond it there is no linear verdict (the linearization would be about a
/// state that is not a motion of the phase).
inline constexpr double kSolutionResidual = 1e-8;

/// The points SteadySpin::orbit_axes holds over one period: the polyline through them is
/// within (2 pi / 1024)^2 / 8 = 5e-6 of the orbit's curve per radian of its cone.
inline constexpr int kOrbitPoints = 1024;

/// The nutation about a periodic orbit [rad]: the angle between H_B at phase time tau
/// (from the orbit's start) and the orbit's H_B direction at that phase (s.orbit_axes,
/// interpolated); with a `slack` > 0 (a clock that may lag), the nearest point of the
/// closed polyline within that share of a period of the phase (each segment taken flat).
double AngleFromOrbit(const SteadySpin& s, double tau, const math::Vec3& H_B, double slack);

/// The steady motion of `flow` near `y_guess` and its modes. y_guess: a state of the
/// phase (H_B is turned onto the principal axis of the held body nearest it). Steady
/// where F does not depend on time and no winding hinge that F depends on turns; periodic
/// where F repeats with flow.period or such a hinge turns (floquet.h); none otherwise.
SteadySpin LinearizeSteadySpin(const ReducedFlow& flow, const Eigen::VectorXd& y_guess);

/// The reduced flow of a hinge system's phase from time t (its free set as it is now),
/// lasting `length` [s]; `period`: see ReducedFlow; `winding`: the free hinges (free
/// order) that can turn without bound, with their axes in B (empty where it moves).
/// A phase that is not autonomous (a prescribed hinge moving in a way that changes the
/// inertia, a motor whose torque depends on time) and not periodic has no steady motion:
/// reason says so.
ReducedFlow FlowOf(const schedule::FreeHingeSystem& sys,
                   double t,
                   double length,
                   double period,
                   std::vector<int> winding,
                   std::vector<math::Vec3> winding_axes);

/// The reduced flow of a rigid body with inertia J_B and rotor momentum h_r (held).
ReducedFlow FlowOf(const math::Mat3& J_B, const math::Vec3& h_r);

/// The largest |eigenvalue| of the held body's momentum equation H' = H x J_B^-1 (H - h_r)
/// linearized at H_B [rad/s]: its nutation frequency in B about a steady spin (or the
/// divergence rate about an intermediate axis). The envelope's window is one period.
double HeldNutationRate(const math::Mat3& J_B, const math::Vec3& h_r, const math::Vec3& H_B);

/// Eigenvalues smaller than this fraction of the spin rate are zero (the conserved |H|,
/// a free rotor's momentum) or neutral (their real part).
inline constexpr double kNeutralRate = 1e-9;

}  // namespace deploysim::analysis
