#pragma once

/// The explicit Runge-Kutta stage loop in a vector space, generic over the state size,
/// used by the rigid-body stepper in (H_B, q_NB) coordinates (explicit_rk.h) and by tests
/// on other ODEs (the seed's appendix B oscillator). The Lie-group steppers (rkmk.cc,
/// shape_integrate.cc) have stage loops of their own: their stages live in the Lie
/// algebra and are mapped back through exp, which this loop does not model.

#include <Eigen/Core>
#include <array>

#include "deploysim/integrators/butcher_tableau.h"
#include "deploysim/integrators/dense_output.h"

namespace deploysim::integrators {

/// The increment y1 - y0 = h sum b_i k_i of one step of the tableau for y' = f(t, y)
/// from (t, y) with step h (returned separately from y0 so that callers can add it with
/// compensated summation). Stage times with c_i = 1 are exactly t + h, so a step that
/// ends on a breakpoint evaluates those stages at the breakpoint itself.
/// If `error` is non-null and the tableau has an embedded solution, it receives
/// h * sum (b_i - b_hat_i) k_i. If `stages` is non-null it receives the stage
/// derivatives k_i (for the continuous extensions, dense_output.h).
template <int N, class F>
Eigen::Matrix<double, N, 1> RkIncrement(
    const ButcherTableau& tab,
    F&& f,
    double t,
    const Eigen::Matrix<double, N, 1>& y,
    double h,
    Eigen::Matrix<double, N, 1>* error = nullptr,
    std::array<Eigen::Matrix<double, N, 1>, kMaxRkStages>* stages = nullptr) {
  using Vec = Eigen::Matrix<double, N, 1>;
  const int s = tab.stages();
  const double t_end = t + h;
  std::array<Vec, kMaxRkStages> local;
  std::array<Vec, kMaxRkStages>& k = stages != nullptr ? *stages : local;
  for (int i = 0; i < s; ++i) {
    Vec yi = y;
    for (int j = 0; j < i; ++j) {
      const double aij = tab.a[i][j];
      if (aij != 0.0) yi += (h * aij) * k[j];
    }
    const double ci = tab.c[i];
    k[i] = f(ci == 1.0 ? t_end : t + ci * h, yi);
  }
  Vec dy = Vec::Zero();
  for (int i = 0; i < s; ++i) {
    if (tab.b[i] != 0.0) dy += (h * tab.b[i]) * k[i];
  }
  if (error != nullptr && !tab.b_hat.empty()) {
    error->setZero();
    for (int i = 0; i < s; ++i) {
      const double d = tab.b[i] - tab.b_hat[i];
      if (d != 0.0) *error += (h * d) * k[i];
    }
  }
  return dy;
}

/// One step of the tableau: y0 + RkIncrement(...).
template <int N, class F>
Eigen::Matrix<double, N, 1> RkStep(const ButcherTableau& tab,
                                   F&& f,
                                   double t,
                                   const Eigen::Matrix<double, N, 1>& y,
                                   double h,
                                   Eigen::Matrix<double, N, 1>* error = nullptr) {
  return y + RkIncrement<N>(tab, f, t, y, h, error);
}

}  // namespace deploysim::integrators
