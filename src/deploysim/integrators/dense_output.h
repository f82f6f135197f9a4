#pragma once

/// Internal to the steppers: interpolants of one step [t0, t0 + h] in the variable
/// theta = (t - t0) / h in [0, 1], for any vector-valued solution y (the state of the
/// vector-space methods, the Lie-algebra coordinate u of the Lie-group methods).
///   HermiteCubic:   y and h f at both ends; error O(h^4) (local).
///   HermiteNodes:   y and h f at n nodes; degree 2n - 1, error O(h^{2n}) (local).
///   DopriDense:     the continuous extension of Dormand-Prince 5(4) (Hairer, Norsett,
///                   Wanner I, sec. II.6, the dense output of DOPRI5, from the step's
///                   seven stages (the seventh, FSAL, is f at the step's end); fourth
///                   order: error O(h^5) (local).

#include <Eigen/Core>
#include <array>

#include "deploysim/integrators/butcher_tableau.h"

namespace deploysim::integrators {

template <int N>
using VecN = Eigen::Matrix<double, N, 1>;

/// The continuous extension a Runge-Kutta tableau gets (the same rule for the
/// vector-space and the Lie-group methods): Dormand-Prince's own for DOPRI5, cubic Hermite
/// for methods of order <= 4, Hermite on nodes (partial steps) above.
enum class DenseKind { kDopri, kHermiteCubic, kHermiteNodes };
inline DenseKind ChooseDenseKind(const ButcherTableau& tableau) {
  return &tableau == &DormandPrince54() ? DenseKind::kDopri
         : tableau.order <= 4           ? DenseKind::kHermiteCubic
                                        : DenseKind::kHermiteNodes;
}

constexpr int kMaxRkStages = 16;

/// The interpolants for any Eigen column-vector type V (fixed or dynamic size); the
/// VecN<N> forms below forward to them.
template <class V>
V HermiteCubicV(double th, double h, const V& y0, const V& f0, const V& y1, const V& f1) {
  const double th2 = th * th;
  const double th3 = th2 * th;
  const double h00 = 2.0 * th3 - 3.0 * th2 + 1.0;
  const double h10 = th3 - 2.0 * th2 + th;
  const double h01 = -2.0 * th3 + 3.0 * th2;
  const double h11 = th3 - th2;
  return h00 * y0 + (h10 * h) * f0 + h01 * y1 + (h11 * h) * f1;
}

constexpr int kMaxHermiteNodes = 6;

/// Hermite interpolation on n <= kMaxHermiteNodes nodes x_j in [0, 1] (x_0 = 0,
/// x_{n-1} = 1) with values y_j and derivatives f_j (d/dt; times h for d/dtheta):
/// degree 2n - 1, error O(h^{2n}) (local). Basis with the Lagrange polynomials L_j:
/// H_j = (1 - 2 L_j'(x_j)(x - x_j)) L_j^2, K_j = (x - x_j) L_j^2.
template <class V>
V HermiteNodesV(double th, double h, int n, const double* x, const V* y, const V* f) {
  V out = V::Zero(y[0].size());
  for (int j = 0; j < n; ++j) {
    double L = 1.0;
    double dL = 0.0;  // L_j'(x_j)
    for (int k = 0; k < n; ++k) {
      if (k == j) continue;
      L *= (th - x[k]) / (x[j] - x[k]);
      dL += 1.0 / (x[j] - x[k]);
    }
    const double L2 = L * L;
    const double d = th - x[j];
    out += ((1.0 - 2.0 * dL * d) * L2) * y[j] + (h * d * L2) * f[j];
  }
  return out;
}

template <class V>
V DopriDenseV(double th, double h, const V& y0, const V& y1, const std::array<V, kMaxRkStages>& k) {
  // Hairer's DOPRI5 (dopri5.f, CONTD5): the fifth-order solution's dense output.
  constexpr double d1 = -12715105075.0 / 11282082432.0;
  constexpr double d3 = 87487479700.0 / 32700410799.0;
  constexpr double d4 = -10690763975.0 / 1880347072.0;
  constexpr double d5 = 701980252875.0 / 199316789632.0;
  constexpr double d6 = -1453857185.0 / 822651844.0;
  constexpr double d7 = 69997945.0 / 29380423.0;
  const V ydiff = y1 - y0;
  const V bspl = h * k[0] - ydiff;
  const V r4 = ydiff - h * k[6] - bspl;
  const V r5 = h * (d1 * k[0] + d3 * k[2] + d4 * k[3] + d5 * k[4] + d6 * k[5] + d7 * k[6]);
  const double th1 = 1.0 - th;
  return y0 + th * (ydiff + th1 * (bspl + th * (r4 + th1 * r5)));
}

/// Nodes of the Hermite interpolant of high-order methods: the step's ends and three
/// interior points (partial steps), degree 9.
constexpr int kStepHermiteNodes = 5;

/// The continuous extension of one accepted Runge-Kutta step, the same for every
/// Runge-Kutta stepper (vector-space and Lie-group, rigid or with shape coordinates):
/// y(theta) from y0, y1 and the step's stages k by the tableau's DenseKind. What the
/// Hermite forms need beyond the step is computed on first use and kept until Reset:
/// the rate at the step's end, end_rate(), and the interior nodes, node(x, y, f), which
/// sets y and f (the solution and its rate at x h, by a partial step).
template <class V>
class StepInterpolant {
 public:
  /// A new accepted step: nothing computed yet.
  void Reset() { have_f1_ = have_nodes_ = false; }

  template <class EndRate, class Node>
  V At(DenseKind kind,
       double th,
       double h,
       const V& y0,
       const V& y1,
       const std::array<V, kMaxRkStages>& k,
       EndRate&& end_rate,
       Node&& node) {
    if (kind == DenseKind::kDopri) return DopriDenseV<V>(th, h, y0, y1, k);
    if (!have_f1_) {
      f1_ = end_rate();
      have_f1_ = true;
    }
    if (kind == DenseKind::kHermiteCubic) return HermiteCubicV<V>(th, h, y0, k[0], y1, f1_);
    constexpr int n = kStepHermiteNodes;
    if (!have_nodes_) {
      for (int j = 0; j < n; ++j) {
        const auto i = static_cast<std::size_t>(j);
        x_[i] = static_cast<double>(j) / (n - 1);
        if (j == 0) {
          y_[i] = y0;
          f_[i] = k[0];
        } else if (j == n - 1) {
          y_[i] = y1;
          f_[i] = f1_;
        } else {
          node(x_[i], y_[i], f_[i]);
        }
      }
      have_nodes_ = true;
    }
    return HermiteNodesV<V>(th, h, n, x_.data(), y_.data(), f_.data());
  }

 private:
  bool have_f1_ = false, have_nodes_ = false;
  V f1_;
  std::array<double, kMaxHermiteNodes> x_{};
  std::array<V, kMaxHermiteNodes> y_{}, f_{};
};

template <int N>
VecN<N> HermiteCubic(double th,
                     double h,
                     const VecN<N>& y0,
                     const VecN<N>& f0,
                     const VecN<N>& y1,
                     const VecN<N>& f1) {
  return HermiteCubicV<VecN<N>>(th, h, y0, f0, y1, f1);
}

template <int N>
VecN<N> HermiteNodes(
    double th, double h, int n, const double* x, const VecN<N>* y, const VecN<N>* f) {
  return HermiteNodesV<VecN<N>>(th, h, n, x, y, f);
}

template <int N>
VecN<N> DopriDense(double th,
                   double h,
                   const VecN<N>& y0,
                   const VecN<N>& y1,
                   const std::array<VecN<N>, kMaxRkStages>& k) {
  return DopriDenseV<VecN<N>>(th, h, y0, y1, k);
}

}  // namespace deploysim::integrators
