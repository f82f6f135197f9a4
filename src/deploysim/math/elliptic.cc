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
/// kAgmTol^2 / 16 in the mean, below long-double rounding.
constexpr long double kAgmTol = 1e-10L;
/// Below this argument sn, cn, dn come from their Taylor series (error O(x^4) < 1e-36);
/// avoids cot(x) overflow in the Landen recursion for tiny x.
constexpr long double kSeriesBelow = 1e-9L;

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

/// K in long double from the arithmetic-geometric mean: K = pi / (2 AGM(1, sqrt(mc))).
long double KLongDouble(double mc) {
  if (mc == 0.0) return std::numeric_limits<long double>::infinity();
  long double a = 1.0L;
  long double b = std::sqrt(static_cast<long double>(mc));
  for (int i = 0; i < 64 && std::abs(a - b) > 4 * std::numeric_limits<long double>::epsilon() * a;
       ++i) {
    const long double an = 0.5L * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  const long double pi = 3.14159265358979323846264338327950288L;
  return pi / (a + b);
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
  m_ = 1.0L - static_cast<long double>(mc);
  sqrt_mc_ = std::sqrt(static_cast<long double>(mc));
  K_ = EllipticK(mc);
  K_ld_ = KLongDouble(mc);
  if (mc == 0.0) return;
  // Bulirsch's AGM table: a_0 = 1, b_0 = sqrt(mc), b_{i+1} = sqrt(a_i b_i).
  long double a = 1.0L;
  long double emc = mc;
  long double c = 1.0L;
  for (int i = 0; i < kMaxLevels; ++i) {
    levels_ = i + 1;
    a_[i] = a;
    emc = std::sqrt(emc);
    b_[i] = emc;
    c = 0.5 * (a + emc);
    if (std::abs(a - emc) <= kAgmTol * a) break;
    emc *= a;
    a = c;
  }
  agm_ = c;
}

JacobiElliptic::Extended JacobiElliptic::Landen(long double x) const {
  if (x < kSeriesBelow) {
    const long double x2 = x * x;
    return {x * (1.0L - (1.0L + m_) * x2 / 6.0L), 1.0L - 0.5L * x2, 1.0L - 0.5L * m_ * x2};
  }
  // Bulirsch (1965), sncndn: descend with cot(agm x), ascend through the AGM table.
  const long double v = x * agm_;  // in (0, pi/4]
  long double a = 1 / std::tan(v);
  long double c = agm_ * a;
  long double dn = 1.0L;
  for (int i = levels_ - 1; i >= 0; --i) {
    const long double b = a_[i];
    a *= c;
    c *= dn;
    dn = (b_[i] + a) / (b + a);
    a = c / b;
  }
  const long double sn = 1.0L / std::sqrt(c * c + 1.0L);
  return {sn, c * sn, dn};
}

SnCnDn JacobiElliptic::OfReduced(long double r) const {
  const double sign = r < 0 ? -1.0 : 1.0;
  const long double x = std::abs(r);
  if (mc_ == 0.0) {
    const double xd = static_cast<double>(x);
    const double sech = 1.0 / std::cosh(xd);
    return {sign * std::tanh(xd), sech, sech};
  }
  if (x <= 0.5L * K_ld_) {
    const Extended f = Landen(x);
    return {sign * static_cast<double>(f.sn), static_cast<double>(f.cn), static_cast<double>(f.dn)};
  }
  // x = K - y: sn(x) = cd(y), cn(x) = sqrt(mc) sd(y), dn(x) = sqrt(mc) nd(y). y < 0 only by
  // rounding (x a hair above K), where the odd sn(y) gives cn its correct sign.
  const long double y = K_ld_ - x;
  const Extended g = Landen(std::abs(y));
  const long double sn_y = y < 0 ? -g.sn : g.sn;
  return {sign * static_cast<double>(g.cn / g.dn), static_cast<double>(sqrt_mc_ * sn_y / g.dn),
          static_cast<double>(sqrt_mc_ / g.dn)};
}

JacobiElliptic::Reduced JacobiElliptic::Evaluate(double u) const {
  Reduced out{};
  if (mc_ == 0.0 || std::abs(u) <= K_) {
    out.j = 0.0;
    out.r = u;
    out.at_r = OfReduced(static_cast<long double>(u));
    out.at_u = out.at_r;
    return out;
  }
  const long double two_k = 2.0L * K_ld_;
  const long double j = std::nearbyint(static_cast<long double>(u) / two_k);
  const long double r = static_cast<long double>(u) - j * two_k;
  out.j = static_cast<double>(j);
  out.r = static_cast<double>(r);
  out.at_r = OfReduced(r);
  const bool odd = std::fmod(std::abs(out.j), 2.0) == 1.0;
  out.at_u = odd ? SnCnDn{-out.at_r.sn, -out.at_r.cn, out.at_r.dn} : out.at_r;
  return out;
}

SnCnDn JacobiElliptic::operator()(double u) const { return Evaluate(u).at_u; }

SnCnDn JacobiSnCnDn(double u, double mc) { return JacobiElliptic(mc)(u); }

}  // namespace deploysim::math
