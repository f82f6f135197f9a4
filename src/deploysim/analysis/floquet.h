#pragma once

/// Periodic solutions of y' = F(t, y) and their Floquet multipliers (docs/design.md 2.8,
/// "Periodic steady motions").
///
/// A steady motion that is not at rest in the hub's frame (a damper riding a spinning
/// rotor: its position turns with the rotor) is a periodic orbit y(t + T) = y(t) + a, a
/// the advance of a winding angle (2 pi for a rotor's turn, 0 otherwise). It is found by
/// shooting: Gauss-Newton on Phi_T(y0) - y0 - a = 0 with |H_B(0)| = |H|, the period T an
/// unknown when F does not depend on time (then one coordinate of y0, the phase, is held)
/// and given when F is T-periodic in time (a rotor held at a steady rate by its motor).
/// Phi_T is the flow map over one period, integrated by Fehlberg's eighth-order formula at
/// a fixed step: a fixed step makes the discrete map a smooth function of y0, so that its
/// differences are its derivative (an adaptive step's choices would make the map jagged
/// at the tolerance). The monodromy matrix dPhi_T/dy0 comes from central differences of
/// the flow map with one Richardson extrapolation (as the steady Jacobian does); its
/// eigenvalues mu are the Floquet multipliers, a mode growing by |mu| per period: the rate
/// ln|mu| / T, and turning by arg(mu) / T (frequency known modulo 2 pi / T).

#include <Eigen/Core>
#include <complex>
#include <functional>
#include <string>
#include <vector>

namespace deploysim::analysis {

/// y' = F(t, y), t from the phase's start [s].
using TimeRhs = std::function<Eigen::VectorXd(double t, const Eigen::VectorXd& y)>;

/// dg/dy at y by central differences with one Richardson extrapolation,
/// D = (4 D(h/2) - D(h)) / 3 with h = 1e-4 of each coordinate's scale: error O(h^4) plus
/// rounding ~ eps |g| / h (~1e-12 relative). The steady spin's Jacobian and the monodromy
/// matrix are both this.
Eigen::MatrixXd RichardsonJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& g,
                                   const Eigen::VectorXd& y,
                                   const Eigen::VectorXd& scale);

/// y(t0 + T) from y(t0) = y0, in `steps` fixed Fehlberg 7(8) steps.
Eigen::VectorXd FlowMap(
    const TimeRhs& f, double t0, const Eigen::VectorXd& y0, double T, int steps);

/// What is sought.
struct OrbitProblem {
  TimeRhs rhs;
  Eigen::VectorXd scale;      ///< each coordinate's scale (differences step 1e-4 of it)
  Eigen::VectorXd advance;    ///< a: y(T) - y(0) on the orbit (a winding angle's 2 pi)
  double period_guess = 0.0;  ///< [s] > 0
  bool period_fixed = false;  ///< F is periodic in t with period_guess: T is not sought
  int phase = -1;             ///< the coordinate held (T sought); -1: none
  double momentum = 0.0;      ///< |H|: |y0.head<3>()| is held to it
  double fastest = 0.0;       ///< [1/s] the largest rate of the motion (sets the step)
  /// The phase's state (empty: y_guess): where the orbits form a family (a conserved
  /// quantity beside |H|, as a free rotor's rate), the member with its conserved values.
  Eigen::VectorXd reference;
  /// Linear functions c . y that F conserves (a free rotor's momentum against a body that
  /// is symmetric about its axis): held at the reference's values exactly. Without them,
  /// the conserved quantities the monodromy shows are held to first order.
  std::vector<Eigen::VectorXd> invariants;
};

struct PeriodicOrbit {
  bool found = false;
  std::string reason;
  Eigen::VectorXd y0;
  double period = 0.0;  ///< [s]
  int steps = 0;        ///< the flow map's fixed steps per period
  /// |Phi_T(y0) - y0 - a| over the scale of each coordinate, relative (the angles' part
  /// per radian, the momenta's per |H|).
  double residual = 0.0;
  Eigen::MatrixXd monodromy;  ///< dPhi_T / dy0 at the orbit
};

/// The periodic orbit of `p` from y_guess, with its monodromy matrix.
PeriodicOrbit SolvePeriodicOrbit(const OrbitProblem& p, const Eigen::VectorXd& y_guess);

}  // namespace deploysim::analysis
