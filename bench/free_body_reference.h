#pragma once

// An independent high-precision reference for the torque-free rigid body with constant
// principal moments I = (I0, I1, I2) along the body axes, written here and sharing no code
// with src/ (neither its integrators nor its closed form nor its extended precision):
//
//   dH/dt = H x w,   w = (H0/I0, H1/I1, H2/I2),   dq/dt = 1/2 q (0, w)   (Hamilton, q_NB)
//
// integrated by a Taylor series method of order N in double-double arithmetic (a value
// is an unevaluated sum hi + lo of two doubles, ~32 significant digits; sums and
// products by the error-free transformations TwoSum and TwoProd with std::fma). The
// system is quadratic, so the Taylor coefficients follow exactly from Cauchy products:
//   H_{k+1} = 1/(k+1) sum_j H_j x w_{k-j},   q_{k+1} = 1/(2(k+1)) sum_j q_j (0, w_{k-j}).
// The step h makes the last two terms of the series below `eps` (relative to |H| for the
// momentum): h = min_j (eps / |x_j|)^(1/j), j = N-1, N (Jorba & Zou 2005). Every step's
// polynomial is kept, so the solution is known at any time with the same accuracy.

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/math/types.h"

namespace deploysim::bench {

/// Double-double number: the unevaluated sum hi + lo, |lo| <= ulp(hi)/2.
struct DD {
  double hi = 0.0;
  double lo = 0.0;
  DD() = default;
  DD(double h) : hi(h) {}  // NOLINT(google-explicit-constructor): exact widening.
  DD(double h, double l) : hi(h), lo(l) {}
};

inline DD TwoSum(double a, double b) {
  const double s = a + b;
  const double bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}
inline DD FastTwoSum(double a, double b) {  // |a| >= |b|
  const double s = a + b;
  return {s, b - (s - a)};
}
inline DD operator+(const DD& a, const DD& b) {
  DD s = TwoSum(a.hi, b.hi);
  const DD t = TwoSum(a.lo, b.lo);
  s.lo += t.hi;
  s = FastTwoSum(s.hi, s.lo);
  s.lo += t.lo;
  return FastTwoSum(s.hi, s.lo);
}
inline DD operator-(const DD& a) { return {-a.hi, -a.lo}; }
inline DD operator-(const DD& a, const DD& b) { return a + (-b); }
inline DD operator*(const DD& a, const DD& b) {
  const double p = a.hi * b.hi;
  double e = std::fma(a.hi, b.hi, -p);
  e += a.hi * b.lo + a.lo * b.hi;
  return FastTwoSum(p, e);
}
inline DD operator/(const DD& a, const DD& b) {
  const double q1 = a.hi / b.hi;
  DD r = a - b * DD(q1);
  const double q2 = r.hi / b.hi;
  r = r - b * DD(q2);
  const double q3 = r.hi / b.hi;
  return FastTwoSum(q1, q2) + DD(q3);
}
inline double ToDouble(const DD& a) { return a.hi + a.lo; }

class FreeBodyReference {
 public:
  /// From H_B(t0) and q_NB(t0) (Eigen quaternion, unit) over [t0, t_end].
  FreeBodyReference(const math::Vec3& principal_moments,
                    const math::Vec3& H0,
                    const math::Quat& q0,
                    double t0,
                    double t_end,
                    int order = 28,
                    double eps = 1e-30)
      : order_(order) {
    if (order < 4 || order > 60)
      throw std::invalid_argument("FreeBodyReference: order = " + std::to_string(order) +
                                  ": must be in [4, 60]");
    if (!(t_end > t0)) throw std::invalid_argument("FreeBodyReference: t_end must be > t0");
    for (int i = 0; i < 3; ++i) {
      if (!(principal_moments[i] > 0.0))
        throw std::invalid_argument("FreeBodyReference: principal moments must be > 0");
      inv_I_[static_cast<std::size_t>(i)] = DD(1.0) / DD(principal_moments[i]);
    }
    for (int k = 0; k <= order_ + 1; ++k) inv_.push_back(DD(1.0) / DD(static_cast<double>(k)));
    const double M = H0.norm();
    Point x;
    x[0] = H0[0];
    x[1] = H0[1];
    x[2] = H0[2];
    x[3] = q0.w();
    x[4] = q0.x();
    x[5] = q0.y();
    x[6] = q0.z();
    double t = t0;
    times_.push_back(t);
    while (t < t_end) {
      std::vector<Point> c = Coefficients(x);
      double h = t_end - t;
      for (int j = order_ - 1; j <= order_; ++j) {
        double n = 0.0;
        for (int i = 0; i < 7; ++i)
          n = std::max(n, std::abs(c[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)].hi) /
                              (i < 3 ? M : 1.0));
        if (n > 0.0) h = std::min(h, std::pow(eps / n, 1.0 / j));
      }
      const double t_next = (t + h >= t_end) ? t_end : t + h;
      const DD s = TwoSum(t_next, -t);  // the step, exactly
      x = Horner(c, s);
      coefficients_.push_back(std::move(c));
      t = t_next;
      times_.push_back(t);
    }
  }

  long steps() const { return static_cast<long>(coefficients_.size()); }

  /// The state at t in double-double: H_B (3), then q_NB as w, x, y, z.
  using Point = std::array<DD, 7>;
  Point StateAt(double t) const { return At(t); }

  math::Vec3 H_B(double t) const {
    const Point x = At(t);
    return math::Vec3(ToDouble(x[0]), ToDouble(x[1]), ToDouble(x[2]));
  }
  math::Quat q_NB(double t) const {
    const Point x = At(t);
    return math::Quat(ToDouble(x[3]), ToDouble(x[4]), ToDouble(x[5]), ToDouble(x[6]));
  }

  /// Times of the sign changes of H_B[axis] in (t0, t_end), each to ~1 ulp of its step
  /// (bisection on the step's polynomial).
  std::vector<double> SignChanges(int axis) const {
    std::vector<double> out;
    const std::size_t a = static_cast<std::size_t>(axis);
    for (std::size_t k = 0; k < coefficients_.size(); ++k) {
      const auto& c = coefficients_[k];
      const DD s_end = TwoSum(times_[k + 1], -times_[k]);
      auto g = [&](const DD& s) { return ToDouble(Horner(c, s)[a]); };
      const double g0 = ToDouble(c[0][a]);
      const double g1 = g(s_end);
      if ((g0 < 0.0) == (g1 < 0.0) || g1 == 0.0) continue;
      double lo = 0.0, hi = ToDouble(s_end);
      for (int it = 0; it < 200 && hi - lo > 0.0; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        if ((g(DD(mid)) < 0.0) == (g0 < 0.0))
          lo = mid;
        else
          hi = mid;
      }
      out.push_back(ToDouble(DD(times_[k]) + DD(0.5 * (lo + hi))));
    }
    return out;
  }

 private:
  std::vector<Point> Coefficients(const Point& x0) const {
    const std::size_t N = static_cast<std::size_t>(order_);
    std::vector<Point> c(N + 1);
    std::vector<std::array<DD, 3>> w(N + 1);
    c[0] = x0;
    for (std::size_t k = 0; k < N; ++k) {
      for (std::size_t i = 0; i < 3; ++i) w[k][i] = c[k][i] * inv_I_[i];
      std::array<DD, 7> sum{};
      for (std::size_t j = 0; j <= k; ++j) {
        const Point& a = c[j];
        const std::array<DD, 3>& b = w[k - j];
        // H x w
        sum[0] = sum[0] + (a[1] * b[2] - a[2] * b[1]);
        sum[1] = sum[1] + (a[2] * b[0] - a[0] * b[2]);
        sum[2] = sum[2] + (a[0] * b[1] - a[1] * b[0]);
        // q (0, w), Hamilton: (qw, qv)(0, w) = (-qv.w, qw w + qv x w)
        sum[3] = sum[3] - (a[4] * b[0] + a[5] * b[1] + a[6] * b[2]);
        sum[4] = sum[4] + (a[3] * b[0] + a[5] * b[2] - a[6] * b[1]);
        sum[5] = sum[5] + (a[3] * b[1] + a[6] * b[0] - a[4] * b[2]);
        sum[6] = sum[6] + (a[3] * b[2] + a[4] * b[1] - a[5] * b[0]);
      }
      const DD f = inv_[k + 1];
      const DD half_f = f * DD(0.5);
      for (std::size_t i = 0; i < 3; ++i) c[k + 1][i] = sum[i] * f;
      for (std::size_t i = 3; i < 7; ++i) c[k + 1][i] = sum[i] * half_f;
    }
    return c;
  }

  static Point Horner(const std::vector<Point>& c, const DD& s) {
    Point x = c.back();
    for (std::size_t k = c.size() - 1; k-- > 0;) {
      for (std::size_t i = 0; i < 7; ++i) x[i] = x[i] * s + c[k][i];
    }
    return x;
  }

  Point At(double t) const {
    if (!(t >= times_.front() && t <= times_.back()))
      throw std::invalid_argument("FreeBodyReference: t = " + std::to_string(t) +
                                  " is outside the reference's interval");
    auto it = std::upper_bound(times_.begin(), times_.end(), t);
    std::size_t k = static_cast<std::size_t>(it - times_.begin());
    k = k == 0 ? 0 : k - 1;
    if (k >= coefficients_.size()) k = coefficients_.size() - 1;
    return Horner(coefficients_[k], TwoSum(t, -times_[k]));
  }

  int order_;
  std::array<DD, 3> inv_I_{};
  std::vector<DD> inv_;  // 1/k
  std::vector<double> times_;
  std::vector<std::vector<Point>> coefficients_;
};

}  // namespace deploysim::bench
