#pragma once

/// The explicit Runge-Kutta stage loop, the one every Runge-Kutta stepper runs: the
/// vector-space steppers on (H_B, q_NB) (explicit_rk.h, and tests on other ODEs), the
/// rigid-body Lie-group steppers (rkmk.cc) and the shape integrator (shape_integrate.cc).
/// It is written in increment form, stage i evaluated at base + sum_j h a_ij k_j: base is
/// the state y0 for a vector space and 0 for a Lie group, whose stages live in the Lie
/// algebra and are mapped back through exp by the stage function itself. Generic over
/// the vector type (fixed size or Eigen::VectorXd; no allocation once sized).

#include <Eigen/Core>
#include <array>

#include "deploysim/integrators/butcher_tableau.h"
#include "deploysim/integrators/dense_output.h"

namespace deploysim::integrators {

/// The stages k_1 .. k_{s-1} of one step from t with step h, k_0 given (the rate at the
/// step's start): f(t_i, Y_i, k_i) sets k_i = F(t_i, Y_i) with Y_i = base + sum_{j<i}
/// h a_ij k_j (`Y` is scratch) and t_i = t + c_i h, exactly t + h where c_i = 1 (a step
/// that ends on a breakpoint evaluates those stages at the breakpoint itself).
template <class Vec, class F>
void RkStages(const ButcherTableau& tab,
              F&& f,
              double t,
              double h,
              const Vec& base,
              Vec& Y,
              std::array<Vec, kMaxRkStages>& k) {
  const int s = tab.stages();
  const double t_end = t + h;
  for (int i = 1; i < s; ++i) {
    const auto row = static_cast<std::size_t>(i);
    Y = base;
    for (int j = 0; j < i; ++j) {
      const double aij = tab.a[row][static_cast<std::size_t>(j)];
      if (aij != 0.0) Y += (h * aij) * k[static_cast<std::size_t>(j)];
    }
    const double ci = tab.c[row];
    f(ci == 1.0 ? t_end : t + ci * h, Y, k[row]);
  }
}

/// out = h sum_i (w_i - w_hat_i) k_i over the tableau's stages, summed from 0 (w_hat null:
/// h sum_i w_i k_i). With w = b: the step's increment; with w = b, w_hat = b_hat: the
/// embedded error estimate. `out` must be sized like the stages.
template <class Vec>
void RkWeightedSum(const std::vector<double>& w,
                   const std::vector<double>* w_hat,
                   double h,
                   const std::array<Vec, kMaxRkStages>& k,
                   Vec& out) {
  out.setZero();
  for (std::size_t i = 0; i < w.size(); ++i) {
    const double d = w_hat != nullptr ? w[i] - (*w_hat)[i] : w[i];
    if (d != 0.0) out += (h * d) * k[i];
  }
}

/// The increment y1 - y0 = h sum b_i k_i of one step of the tableau for y' = f(t, y)
/// from (t, y) with step h (returned separately from y0 so that callers can add it with
/// compensated summation), by RkStages with base y. If `error` is non-null and the
/// tableau has an embedded solution, it receives h * sum (b_i - b_hat_i) k_i. If
/// `stages` is non-null it receives the stage derivatives k_i (for the continuous
/// extensions, dense_output.h).
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
  std::array<Vec, kMaxRkStages> local;
  std::array<Vec, kMaxRkStages>& k = stages != nullptr ? *stages : local;
  k[0] = f(t, y);
  Vec Y;
  RkStages<Vec>(
      tab, [&f](double ti, const Vec& yi, Vec& ki) { ki = f(ti, yi); }, t, h, y, Y, k);
  Vec dy;
  RkWeightedSum<Vec>(tab.b, nullptr, h, k, dy);
  if (error != nullptr && !tab.b_hat.empty()) RkWeightedSum<Vec>(tab.b, &tab.b_hat, h, k, *error);
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
