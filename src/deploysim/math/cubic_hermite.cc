#include "deploysim/math/cubic_hermite.h"

#include <algorithm>
#include <cmath>

namespace deploysim::math {

double CubicHermiteMinimum(double t0, double f0, double d0, double t1, double f1, double d1) {
  return CubicHermiteMinimumAt(t0, f0, d0, t1, f1, d1).value;
}

HermitePoint CubicHermiteMinimumAt(
    double t0, double f0, double d0, double t1, double f1, double d1) {
  // p(u) on u in [0, 1]: p(0) = f0, p(1) = f1, p'(0) = h d0, p'(1) = h d1.
  const double h = t1 - t0;
  const double m0 = h * d0, m1 = h * d1;
  // p(u) = f0 + c1 u + c2 u^2 + c3 u^3.
  const double c1 = m0;
  const double c2 = 3.0 * (f1 - f0) - 2.0 * m0 - m1;
  const double c3 = 2.0 * (f0 - f1) + m0 + m1;
  auto p = [&](double u) { return f0 + u * (c1 + u * (c2 + u * c3)); };
  HermitePoint best = f1 < f0 ? HermitePoint{t1, f1} : HermitePoint{t0, f0};
  auto consider = [&](double u) {
    if (u > 0.0 && u < 1.0 && p(u) < best.value) best = {t0 + u * h, p(u)};
  };
  // p'(u) = c1 + 2 c2 u + 3 c3 u^2 = 0.
  const double A = 3.0 * c3, B = 2.0 * c2, C = c1;
  if (std::abs(A) < 1e-300) {
    if (B != 0.0) {
      consider(-C / B);
    }
    return best;
  }
  const double disc = B * B - 4.0 * A * C;
  if (disc < 0.0) return best;
  const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
  for (const double u : {q / A, q != 0.0 ? C / q : -1.0}) consider(u);
  return best;
}

}  // namespace deploysim::math
