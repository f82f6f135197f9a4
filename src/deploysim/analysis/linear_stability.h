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
  /// F at another time (empty: F does not depend on time): the steady spin exists only
  /// where the two agree.
  std::function<Eigen::VectorXd(const Eigen::VectorXd& y)> rhs_later;
  /// The power of the sinks (dampers, friction) at y [W] (<= 0); empty: no sink.
  std::function<double(const Eigen::VectorXd& y)> sink_power;
  /// J_B [kg m^2] and the rotors' momentum h_r [kg m^2/s] at y (the quasi-rigid body).
  std::function<void(const Eigen::VectorXd& y, math::Mat3& J_B, math::Vec3& h_r)> rigid;
  /// Free hinges whose angle is cyclic (rotors), in free order; found when empty.
  std::vector<int> cyclic;
};

/// One mode of small motions about the steady spin.
struct SpinMode {
  std::complex<double> lambda;  ///< [1/s] eigenvalue: growth rate + i frequency
  /// How much of the mode is a tilt of H_B in the body (the nutation): the transverse
  /// momentum perturbation over |H| against the mode's whole (scaled) eigenvector, 0..1.
  double momentum_share = 0.0;
};

/// The steady spin and its linear stability.
struct SteadySpin {
  bool found = false;
  std::string reason;                   ///< why there is none (found false)
  Eigen::VectorXd y;                    ///< the relative equilibrium (H_B, theta_f, p_f)
  math::Vec3 w_B = math::Vec3::Zero();  ///< [rad/s] the hub's spin there
  double residual = 0.0;                ///< |F(y*)| relative to |H| |w| (cyclic angles left out)
  std::vector<SpinMode> modes;          ///< every non-zero eigenvalue, largest real part first
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

/// The relative equilibrium of `flow` near `y_guess` and its modes. y_guess: a state of
/// the phase (H_B is turned onto the principal axis of the held body nearest it).
SteadySpin LinearizeSteadySpin(const ReducedFlow& flow, const Eigen::VectorXd& y_guess);

/// The reduced flow of a hinge system's phase at time t (its free set as it is now);
/// rhs_later at t_later (a time of the same phase).
/// A phase that is not autonomous (a prescribed hinge moving in a way that changes the
/// inertia, a motor whose torque depends on time) has no steady spin: reason says so.
ReducedFlow FlowOf(const schedule::FreeHingeSystem& sys, double t, double t_later);

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
