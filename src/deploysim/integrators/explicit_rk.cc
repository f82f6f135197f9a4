#include "deploysim/integrators/explicit_rk.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/integrators/rk_engine.h"

namespace deploysim::integrators {

namespace {

using Vec7 = Eigen::Matrix<double, 7, 1>;

// y = (H_B, q.coeffs() = (x, y, z, w)).
Vec7 Derivative(const Problem& problem, double t, const Vec7& y) {
  const dynamics::InertiaSample s = problem.Sample(t);
  const math::Vec3 H = y.head<3>();
  const math::Vec3 w = dynamics::AngularVelocity(s, H);
  const math::Quat q(y[6], y[3], y[4], y[5]);
  Vec7 dy;
  dy.head<3>() = dynamics::MomentumRate(H, w);
  dy.tail<4>() = dynamics::QuaternionRate(q, w);
  return dy;
}

}  // namespace

ExplicitRkStepper::ExplicitRkStepper(const ButcherTableau& tableau,
                                     std::string name,
                                     std::string summary)
    : tableau_(tableau) {
  info_.name = std::move(name);
  info_.summary = std::move(summary);
  info_.reference = tableau.reference;
  info_.order = tableau.order;
  info_.error_order = tableau.b_hat.empty() ? 0 : tableau.embedded_order;
  info_.adaptive = !tableau.b_hat.empty();
  info_.lie_group = false;
}

StepAttempt ExplicitRkStepper::Step(const Problem& problem,
                                    const State& y,
                                    double h,
                                    const Tolerances& tol) const {
  Vec7 y0;
  y0.head<3>() = y.H_B;
  y0.tail<4>() = y.q_NB.coeffs();
  Vec7 err = Vec7::Zero();
  auto f = [&problem](double t, const Vec7& v) { return Derivative(problem, t, v); };
  const Vec7 dy = RkIncrement<7>(tableau_, f, y.t, y0, h, info_.adaptive ? &err : nullptr);
  // Compensated (Kahan) summation of the momentum: near the separatrix the distance to
  // it, 2T I2 - M^2, is a small difference of large numbers, and the plain update's
  // rounding (1e-16 |H| per step) moves it enough to scatter the flip times by ~1e-9 s
  // over 40 s; carrying the rounding error removes most of that.
  Vec7 y1 = y0 + dy;
  const math::Vec3 d = dy.head<3>() + y.H_B_carry;
  const math::Vec3 H1 = y.H_B + d;
  y1.head<3>() = H1;
  StepAttempt out;
  if (info_.adaptive) {
    const double scale = problem.momentum_scale();
    double norm = 0.0;
    for (int i = 0; i < 7; ++i) {
      const double ref = std::max(std::abs(y0[i]), std::abs(y1[i]));
      const double w = i < 3 ? tol.atol * scale + tol.rtol * ref : tol.atol + tol.rtol * ref;
      norm = std::max(norm, std::abs(err[i]) / w);
    }
    out.error_norm = norm;
  }
  out.result.t = y.t + h;
  out.result.H_B = H1;
  out.result.H_B_carry = (y.H_B - H1) + d;
  out.result.q_NB = math::Quat(y1[6], y1[3], y1[4], y1[5]).normalized();
  return out;
}

}  // namespace deploysim::integrators
