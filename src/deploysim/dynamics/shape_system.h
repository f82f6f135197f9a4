#pragma once

/// A torque-free body with free shape coordinates (docs/design.md 2.7): the hub's attitude
/// R_NB plus m free hinges with angles theta_f [rad] and conjugate momenta p_f
/// [kg m^2/s = N m s]. With H_B = R_NB^T h_N (h_N constant) the equations are
///   solve M(theta) [w; theta'] = [H_B; p] (minus the prescribed hinges' part)
///   dR_NB/dt = R_NB [w]x,   dtheta_f/dt = theta'_f,   dp_f/dt = dT/dtheta_f + Q_f.
/// The shape state is x = (theta_f, p_f) in R^(2m), optionally followed by accumulators
/// (quadratures such as the work of each source of energy): entries whose rates Evaluate
/// gives, which do not act back on the motion and are left out of the step-size control
/// (their error follows from the motion's). An implementation (schedule's
/// FreeHingeSystem) is evaluated at every Runge-Kutta stage; it may keep scratch space and
/// is then used by one run (one thread) at a time.

#include <Eigen/Core>
#include <vector>

#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/math/types.h"

namespace deploysim::dynamics {

class ShapeSystem {
 public:
  virtual ~ShapeSystem() = default;

  /// m, the number of free hinges; the shape state has 2m entries.
  virtual int free_count() const = 0;

  /// At time t (one-sided at breakpoints) with total momentum H_B [kg m^2/s] and shape
  /// state x = (theta_f, p_f): the hub's angular velocity w_NB_B [rad/s] and
  /// x' = (theta'_f, p'_f) (resized to 2m).
  virtual void Evaluate(double t,
                        const math::Vec3& H_B,
                        const Eigen::VectorXd& x,
                        Side side,
                        math::Vec3& w_NB_B,
                        Eigen::VectorXd& x_dot) const = 0;

  /// Times in (t0, t1) where the right-hand side is not smooth in t (prescribed hinges'
  /// windows): integrators step to them and restart. Ascending. Default: none.
  virtual std::vector<double> Breakpoints(double t0, double t1) const;
};

}  // namespace deploysim::dynamics
