#include "deploysim/math/double_double.h"

#include <array>
#include <cmath>
#include <limits>

namespace deploysim::math {

namespace {

/// pi/2 = kPio2Hi + kPio2Mid + kPio2Lo to ~2^-162 (three-part constant for the Cody-Waite
/// reduction; the first two are the double-double pi/2, kPiDD / 2).
constexpr double kPio2Hi = 0x1.921fb54442d18p+0;
constexpr double kPio2Mid = 0x1.1a62633145c07p-54;
constexpr double kPio2Lo = -0x1.f1976b7ed8fbcp-110;
constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
constexpr double kPio4 = 0x1.921fb54442d18p-1;

/// Number of Taylor terms available: (pi/4)^(2k) / (2k)! < 2^-110 for k >= 15.
constexpr int kMaxTerms = 15;
/// A term below this fraction of the result is dropped (below double-double rounding).
constexpr double kTruncation = 0x1p-110;
/// Terms below this fraction of the result are summed in double: their double rounding
/// error is below 2^-56 * 2^-53 of the result.
constexpr double kDoubleTail = 0x1p-56;

/// c_k = (-1)^k / (2k+1)!, k = 0..kMaxTerms (sin r = sum c_k r^(2k+1)).
const std::array<DoubleDouble, kMaxTerms + 1>& SinCoefficients() {
  static const std::array<DoubleDouble, kMaxTerms + 1> c = [] {
    std::array<DoubleDouble, kMaxTerms + 1> t{};
    t[0] = 1.0;
    for (int k = 1; k <= kMaxTerms; ++k) {
      t[k] = t[k - 1] / -static_cast<double>((2 * k) * (2 * k + 1));  // exact divisor
    }
    return t;
  }();
  return c;
}

/// d_k = (-1)^k / (2k)!, k = 0..kMaxTerms (cos r = sum d_k r^(2k)).
const std::array<DoubleDouble, kMaxTerms + 1>& CosCoefficients() {
  static const std::array<DoubleDouble, kMaxTerms + 1> d = [] {
    const std::array<DoubleDouble, kMaxTerms + 1>& c = SinCoefficients();
    std::array<DoubleDouble, kMaxTerms + 1> t{};
    t[0] = 1.0;
    for (int k = 1; k <= kMaxTerms; ++k) t[k] = c[k - 1] / -static_cast<double>(2 * k);
    return t;
  }();
  return d;
}

}  // namespace

void SincCosOfSquare(const DoubleDouble& t, DoubleDouble* sinc, DoubleDouble* cos) {
  const std::array<DoubleDouble, kMaxTerms + 1>& s = SinCoefficients();
  const std::array<DoubleDouble, kMaxTerms + 1>& c = CosCoefficients();
  const double td = t.hi();
  int n = 0;  // terms 1 .. n kept (cosine terms are the larger: 1/(2k)! > 1/(2k+1)!)
  int m = 0;  // of which 1 .. m in double-double
  double p = td;
  while (n < kMaxTerms && p * std::abs(c[n + 1].hi()) >= kTruncation) {
    ++n;
    if (p * std::abs(c[n].hi()) >= kDoubleTail) m = n;
    p *= td;
  }
  double qs = 0.0, qc = 0.0;
  for (int k = n; k > m; --k) {
    qs = s[k].hi() + td * qs;
    qc = c[k].hi() + td * qc;
  }
  DoubleDouble ps = qs, pc = qc;
  for (int k = m; k >= 1; --k) {
    ps = s[k] + t * ps;
    pc = c[k] + t * pc;
  }
  *sinc = 1.0 + t * ps;
  *cos = 1.0 + t * pc;
}

void SinCos(const DoubleDouble& x, DoubleDouble* sin_x, DoubleDouble* cos_x) {
  if (!std::isfinite(x.hi())) {
    *sin_x = *cos_x = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  DoubleDouble r = x;
  int quadrant = 0;
  if (std::abs(x.hi()) > kPio4) {
    // x = k pi/2 + r: k pi/2 is subtracted part by part, each product exact (TwoProd).
    const double k = std::nearbyint(x.hi() * kTwoOverPi);
    r = ((x - TwoProd(k, kPio2Hi)) - TwoProd(k, kPio2Mid)) - k * kPio2Lo;
    quadrant = static_cast<int>(std::fmod(k, 4.0));
    if (quadrant < 0) quadrant += 4;
  }
  DoubleDouble sinc, c;
  SincCosOfSquare(Square(r), &sinc, &c);
  const DoubleDouble s = r * sinc;
  switch (quadrant) {
    case 0:
      *sin_x = s, *cos_x = c;
      break;
    case 1:
      *sin_x = c, *cos_x = -s;
      break;
    case 2:
      *sin_x = -s, *cos_x = -c;
      break;
    default:
      *sin_x = -c, *cos_x = s;
      break;
  }
}

}  // namespace deploysim::math
