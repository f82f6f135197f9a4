#include "deploysim/math/elliptic.h"

#include <boost/math/special_functions/ellint_rf.hpp>
#include <boost/math/special_functions/ellint_rj.hpp>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace deploysim::math {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kHalfPi = 1.5707963267948966192;
/// AGM stopping rule of Bulirsch's sncndn: |a - b| <= kAgmTol a leaves an error of order
/// kAgmTol^2 / 16 ~ 6e-22 in the mean used by the Landen core, whose relative sensitivity
/// to it is ~ x <= K/2: ~1e-20, far below double rounding of the results (near the
/// zeros, where relative accuracy needs more, the series branch takes over).
constexpr double kAgmTol = 1e-10;
/// K, which sets the reduction u = 2K j + r for all |u|, takes the AGM further, to
/// |a - b| <= kAgmTolK a (error ~6e-34, below double-double rounding).
constexpr double kAgmTolK = 1e-16;
/// Below this argument sn, cn, dn come from their Taylor series (error O(x^4) < 1e-36);
/// avoids cot(x) overflow in the Landen recursion for tiny x.
constexpr double kSeriesBelow = 1e-9;

void CheckMc(double mc, const char* where) {
  if (!(mc >= 0.0 && mc <= 1.0)) {
    std::ostringstream os;
    os.precision(17);
    os << where << ": complementary parameter mc = " << mc
       << " is outside [0, 1] (rule: 0 <= mc = 1 - k^2 <= 1)";
    throw std::invalid_argument(os.str());
  }
}

void CheckPhi(double phi, const char* where) {
  if (!(std::abs(phi) <= kHalfPi)) {
    std::ostringstream os;
    os.precision(17);
    os << where << ": amplitude phi = " << phi << " is outside [-pi/2, pi/2]";
    throw std::invalid_argument(os.str());
  }
}

void CheckN(double n, const char* where) {
  if (!(n < 1.0)) {
    std::ostringstream os;
    os.precision(17);
    os << where << ": characteristic n = " << n << " must be < 1 (no principal values)";
    throw std::invalid_argument(os.str());
  }
}

}  // namespace

double EllipticK(double mc) {
  CheckMc(mc, "EllipticK");
  if (mc == 0.0) return kInf;
  return boost::math::ellint_rf(0.0, mc, 1.0);
}

double EllipticF(double phi, double mc) {
  CheckMc(mc, "EllipticF");
  CheckPhi(phi, "EllipticF");
  const double s = std::sin(phi);
  const double c = std::cos(phi);
  if (s == 0.0) return phi;
  return s * boost::math::ellint_rf(c * c, c * c + mc * s * s, 1.0);
}

double EllipticPi(double n, double phi, double mc) {
  CheckMc(mc, "EllipticPi");
  CheckPhi(phi, "EllipticPi");
  CheckN(n, "EllipticPi");
  const double s = std::sin(phi);
  const double c = std::cos(phi);
  if (s == 0.0) return phi;
  const double c2 = c * c;
  const double d2 = c2 + mc * s * s;
  double pi = s * boost::math::ellint_rf(c2, d2, 1.0);
  if (n != 0.0) pi += n / 3.0 * s * s * s * boost::math::ellint_rj(c2, d2, 1.0, 1.0 - n * s * s);
  return pi;
}

double EllipticPiComplete(double n, double mc) {
  CheckMc(mc, "EllipticPiComplete");
  CheckN(n, "EllipticPiComplete");
  if (mc == 0.0) {
    throw std::invalid_argument("EllipticPiComplete: mc = 0 gives an infinite integral");
  }
  double pi = boost::math::ellint_rf(0.0, mc, 1.0);
  if (n != 0.0) pi += n / 3.0 * boost::math::ellint_rj(0.0, mc, 1.0, 1.0 - n);
  return pi;
}

double InverseJacobi(double sn, double cn, double dn, double mc) {
  CheckMc(mc, "InverseJacobi");
  if (mc == 0.0) {
    if (cn == 0.0) return sn >= 0.0 ? kInf : -kInf;
    return std::asinh(sn / std::abs(cn));
  }
  if (sn == 0.0) return cn >= 0.0 ? 0.0 : 2.0 * EllipticK(mc);
  const double f = sn * boost::math::ellint_rf(cn * cn, dn * dn, 1.0);
  if (cn >= 0.0) return f;
  return std::copysign(2.0 * EllipticK(mc), sn) - f;
}

JacobiElliptic::JacobiElliptic(double mc) : mc_(mc) {
  CheckMc(mc, "JacobiElliptic");
  m_ = 1.0 - DoubleDouble(mc);  // exact
  sqrt_mc_ = Sqrt(DoubleDouble(mc));
  K_ = EllipticK(mc);
  if (mc == 0.0) {
    K_dd_ = kInf;
    return;
  }
  // Bulirsch's AGM table: a_0 = 1, b_0 = sqrt(mc), b_{i+1} = sqrt(a_i b_i), until
  // |a - b| <= kAgmTol a; the mean of the last pair is AGM(1, sqrt(mc)) to kAgmTol^2 / 16.
  DoubleDouble a = 1.0;
  DoubleDouble emc = mc;
  DoubleDouble c = 1.0;
  for (int i = 0; i < kMaxLevels; ++i) {
    levels_ = i + 1;
    a_[i] = a;
    inv_a_[i] = 1.0 / a;
    emc = Sqrt(emc);
    b_[i] = emc;
    c = (a + emc) * 0.5;
    if (Abs(a - emc) <= a * kAgmTol) break;
    emc *= a;
    a = c;
  }
  agm_ = c;
  // K = pi / (2 AGM), the AGM taken on to double-double accuracy.
  DoubleDouble b = Sqrt(emc * a);
  a = c;
  for (int i = 0; i < 8 && Abs(a - b) > a * kAgmTolK; ++i) {
    const DoubleDouble next = (a + b) * 0.5;
    b = Sqrt(a * b);
    a = next;
  }
  K_dd_ = kPiDD / (a + b);
}

JacobiElliptic::Extended JacobiElliptic::Landen(const DoubleDouble& x) const {
  if (x < kSeriesBelow) {
    const DoubleDouble x2 = Square(x);
    return {x * (1.0 - (1.0 + m_) * x2 / 6.0), 1.0 - x2 * 0.5, 1.0 - m_ * x2 * 0.5};
  }
  // Bulirsch (1965), sncndn: descend with cot(agm x), ascend through the AGM table.
  const DoubleDouble v = x * agm_;  // in (0, pi/4]
  DoubleDouble sin_v, cos_v;
  SinCos(v, &sin_v, &cos_v);
  DoubleDouble a = cos_v / sin_v;
  DoubleDouble c = agm_ * a;
  DoubleDouble dn = 1.0;
  for (int i = levels_ - 1; i >= 0; --i) {
    a *= c;
    c *= dn;
    dn = (b_[i] + a) / (a_[i] + a);
    a = c * inv_a_[i];
  }
  const DoubleDouble sn = 1.0 / Sqrt(Square(c) + 1.0);
  return {sn, c * sn, dn};
}

SnCnDn JacobiElliptic::OfReduced(const DoubleDouble& r) const {
  const double sign = r.hi() < 0 ? -1.0 : 1.0;
  const DoubleDouble x = Abs(r);
  if (mc_ == 0.0) {
    const double xd = x.hi();
    const double sech = 1.0 / std::cosh(xd);
    return {sign * std::tanh(xd), sech, sech};
  }
  if (x <= K_dd_ * 0.5) {
    const Extended f = Landen(x);
    return {sign * static_cast<double>(f.sn), static_cast<double>(f.cn), static_cast<double>(f.dn)};
  }
  // x = K - y: sn(x) = cd(y), cn(x) = sqrt(mc) sd(y), dn(x) = sqrt(mc) nd(y). y < 0 only by
  // rounding (x a hair above K), where the odd sn(y) gives cn its correct sign.
  const DoubleDouble y = K_dd_ - x;
  const Extended g = Landen(Abs(y));
  const DoubleDouble sn_y = y.hi() < 0 ? -g.sn : g.sn;
  return {sign * static_cast<double>(g.cn / g.dn), static_cast<double>(sqrt_mc_ * sn_y / g.dn),
          static_cast<double>(sqrt_mc_ / g.dn)};
}

JacobiElliptic::Reduced JacobiElliptic::Evaluate(double u) const {
  Reduced out{};
  if (mc_ == 0.0 || std::abs(u) <= K_) {
    out.j = 0.0;
    out.r = u;
    out.at_r = OfReduced(u);
    out.at_u = out.at_r;
    return out;
  }
  // u = 2K j + r: any integer j near u / 2K will do; r is formed in double-double.
  const DoubleDouble two_k = K_dd_ * 2.0;
  const double j = std::nearbyint(u / two_k.hi());
  const DoubleDouble r = u - two_k * j;
  out.j = j;
  out.r = r.hi();
  out.at_r = OfReduced(r);
  const bool odd = std::fmod(std::abs(out.j), 2.0) == 1.0;
  out.at_u = odd ? SnCnDn{-out.at_r.sn, -out.at_r.cn, out.at_r.dn} : out.at_r;
  return out;
}

SnCnDn JacobiElliptic::operator()(double u) const { return Evaluate(u).at_u; }

SnCnDn JacobiSnCnDn(double u, double mc) { return JacobiElliptic(mc)(u); }

}  // namespace deploysim::math
