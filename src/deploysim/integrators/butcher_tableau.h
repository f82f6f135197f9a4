#pragma once

/// Explicit Runge-Kutta tableaus, with their citations. Shared by the vector-space
/// steppers (explicit_rk.h) and the Lie-group RKMK steppers (rkmk.h).

#include <string>
#include <vector>

namespace deploysim::integrators {

/// c (nodes), A (strictly lower triangular, row-major rows of increasing length),
/// b (weights of the propagated solution), b_hat (embedded weights; empty if none).
struct ButcherTableau {
  std::string name;
  std::string reference;
  int order = 0;
  int embedded_order = 0;
  std::vector<double> c;
  std::vector<std::vector<double>> a;  ///< a[i] has i entries (a[0] is empty).
  std::vector<double> b;
  std::vector<double> b_hat;
  int stages() const { return static_cast<int>(c.size()); }
};

/// Explicit Euler (c = 0, b = 1): first order.
const ButcherTableau& ExplicitEuler();

/// Classic fourth-order Runge-Kutta (Kutta 1901).
/// c = (0, 1/2, 1/2, 1); b = (1/6, 1/3, 1/3, 1/6).
const ButcherTableau& ClassicRk4();

/// Dormand-Prince 5(4), 7 stages, FSAL. J. R. Dormand, P. J. Prince, "A family of
/// embedded Runge-Kutta formulae", J. Comp. Appl. Math. 6 (1980) 19-26; coefficients as
/// in Hairer, Norsett, Wanner, Solving ODEs I, table II.5.2.
const ButcherTableau& DormandPrince54();

/// Fehlberg 7(8), 13 stages, propagating the eighth-order solution (local
/// extrapolation). E. Fehlberg, "Classical fifth-, sixth-, seventh-, and eighth-order
/// Runge-Kutta formulas with stepsize control", NASA TR R-287 (1968), table X.
const ButcherTableau& Fehlberg78();

}  // namespace deploysim::integrators
