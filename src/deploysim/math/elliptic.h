#pragma once

/// Jacobi elliptic functions and Legendre elliptic integrals, parameterised by the
/// COMPLEMENTARY parameter mc = 1 - m (m = k^2 is the parameter, k the modulus), so that
/// they stay exact near the separatrix of the free rigid body, where mc -> 0
/// (docs/design.md section 2.3). Conventions (Abramowitz & Stegun 16, 17; DLMF 19, 22):
///   F(phi|m)    = int_0^phi dtheta / sqrt(1 - m sin^2 theta),   K(m) = F(pi/2|m),
///   Pi(n;phi|m) = int_0^phi dtheta / ((1 - n sin^2 theta) sqrt(1 - m sin^2 theta)),
///   u = F(phi|m)  <=>  phi = am(u|m), sn = sin(am), cn = cos(am), dn = sqrt(1 - m sn^2).
/// Every routine takes mc in [0, 1] and throws std::invalid_argument (naming the value)
/// otherwise. mc = 0 is allowed: sn = tanh, cn = dn = sech, K = +inf.
/// The integrals use Carlson's symmetric forms (Boost.Math ellint_rf, ellint_rj), which
/// take 1 - m sin^2 = cos^2 + mc sin^2 directly and never form 1 - m.

#include <array>

#include "deploysim/math/double_double.h"

namespace deploysim::math {

/// The three Jacobi elliptic functions at one argument.
struct SnCnDn {
  double sn;
  double cn;
  double dn;
};

/// Complete integral of the first kind K(m) = R_F(0, mc, 1); +inf at mc = 0.
/// Accurate to about 1 ulp for every mc in (0, 1] (K ~ ln(4/sqrt(mc)) as mc -> 0).
double EllipticK(double mc);

/// Incomplete integral of the first kind F(phi|m) = s R_F(c^2, c^2 + mc s^2, 1),
/// s = sin(phi), c = cos(phi), for |phi| <= pi/2 (throws otherwise).
double EllipticF(double phi, double mc);

/// Incomplete integral of the third kind, for |phi| <= pi/2 and n < 1 (throws otherwise):
/// Pi(n;phi|m) = s R_F(c^2, d^2, 1) + (n/3) s^3 R_J(c^2, d^2, 1, 1 - n s^2), d^2 = c^2 + mc s^2.
double EllipticPi(double n, double phi, double mc);

/// Complete integral of the third kind Pi(n|m) = R_F(0, mc, 1) + (n/3) R_J(0, mc, 1, 1 - n),
/// n < 1, mc in (0, 1] (throws otherwise).
double EllipticPiComplete(double n, double mc);

/// The argument u in (-2K, 2K] with sn(u|m) = sn, cn(u|m) = cn, dn(u|m) = dn, i.e. the
/// inverse of the Jacobi functions: u = sn R_F(cn^2, dn^2, 1) for cn >= 0 and
/// u = sign(sn) 2K - sn R_F(cn^2, dn^2, 1) for cn < 0 (sn(2K - v) = sn v, cn(2K - v) = -cn v).
/// The three values are passed separately so that callers who know them to full relative
/// accuracy (e.g. from momentum components) keep it; they need only be consistent to
/// rounding. Relative perturbations eps of the inputs move u by O(eps (1 + |u|)).
/// For mc = 0, cn = dn = sech u > 0 and the result is asinh(sn/cn) (+-inf when cn = 0).
double InverseJacobi(double sn, double cn, double dn, double mc);

/// sn, cn, dn for one fixed mc, with the parameter-dependent work done once.
///
/// Algorithm: the argument is reduced by the half period, u = 2K j + r with |r| <= K, in
/// double-double (math::DoubleDouble) with K = pi / (2 AGM(1, sqrt(mc))) from the
/// arithmetic-geometric mean in double-double, so the reduction adds ~1e-31 |u| to the
/// argument's own rounding on every platform. Then sn(u) = (-1)^j sn(r), cn(u) = (-1)^j cn(r),
/// dn(u) = dn(r); r is folded to [0, K/2] by symmetry (x -> K - x: sn = cn/dn, cn = sqrt(mc) sn/dn,
/// dn = sqrt(mc)/dn, which keeps cn's relative accuracy near its zero), and there Bulirsch's
/// descending Landen transformation (R. Bulirsch, Numer. Math. 7 (1965) 78-90, routine sncndn; as
/// in Numerical Recipes 6.11) evaluates sn, cn, dn from the AGM sequence of (1, sqrt(mc)). Every
/// step is a product or quotient of positive numbers. The Landen core runs in double-double: near
/// the separatrix the result's relative sensitivity to the compressed argument agm * x is about x ~
/// K/2 (sech-like decay), which would cost ~10 ulp in double. Measured against 40-digit mpmath
/// values (tests/math/elliptic_test.cpp), mc from 1 to 1e-16 and 0, |u| up to 300 K: 0.8 eps
/// relative where the argument's own rounding does not dominate, i.e. the value of a correctly
/// rounded evaluation at an argument within ~1e-30 |u| of u. Cost ~0.4 us per evaluation on x86-64.
class JacobiElliptic {
 public:
  /// mc in [0, 1]; throws std::invalid_argument otherwise.
  explicit JacobiElliptic(double mc);

  double mc() const { return mc_; }
  /// m = 1 - mc.
  double m() const { return m_.hi(); }
  /// Quarter period K(m) (double); +inf for mc = 0.
  double K() const { return K_; }

  /// sn, cn, dn of u.
  SnCnDn operator()(double u) const;

  /// The functions at u and at its half-period reduction u = 2K j + r, |r| <= K
  /// (j = 0, r = u when mc = 0). at_u = (-1)^j at_r for sn and cn; dn is the same.
  struct Reduced {
    SnCnDn at_u;
    SnCnDn at_r;
    double j;  ///< Number of half periods (an integer value, double to allow large |u|).
    double r;  ///< Reduced argument, |r| <= K up to rounding.
  };
  Reduced Evaluate(double u) const;

 private:
  static constexpr int kMaxLevels = 32;
  struct Extended {
    DoubleDouble sn;
    DoubleDouble cn;
    DoubleDouble dn;
  };
  /// Bulirsch's sncndn for 0 <= x <= K/2, in double-double.
  Extended Landen(const DoubleDouble& x) const;
  /// sn, cn, dn for |r| <= K.
  SnCnDn OfReduced(const DoubleDouble& r) const;

  double mc_;
  DoubleDouble m_;
  DoubleDouble sqrt_mc_;
  double K_;
  DoubleDouble K_dd_;
  int levels_ = 0;
  DoubleDouble agm_ = 1.0;
  std::array<DoubleDouble, kMaxLevels> a_{};      ///< AGM means a_i, a_0 = 1.
  std::array<DoubleDouble, kMaxLevels> inv_a_{};  ///< 1 / a_i.
  std::array<DoubleDouble, kMaxLevels> b_{};      ///< AGM geometric means b_i, b_0 = sqrt(mc).
};

/// sn, cn, dn of u for complementary parameter mc (JacobiElliptic(mc)(u)).
SnCnDn JacobiSnCnDn(double u, double mc);

}  // namespace deploysim::math
