// Tests of math::DoubleDouble (double-double arithmetic from error-free transformations).
//
// (a) Exactness of TwoSum, FastTwoSum and TwoProd: exact integer identities (operands
//     chosen so that the exact result fits in 64-bit integers), bit-for-bit agreement of
//     the two independent exact products (fma and Dekker's split), and, where the compiler
//     has binary128 (__float128, 113 bits, enough to hold every exact result), exact
//     equality in binary128.
// (b) Accuracy of +, -, *, /, Sqrt, SinCos: against binary128 where available, relative
//     error within the proven bounds (Joldes, Muller, Popescu 2017) in u^2 = 2^-106; and
//     everywhere by identities that hold exactly in real arithmetic (round trips, exact
//     integer results, sin^2 + cos^2 = 1, double angles, known values).

#include "deploysim/math/double_double.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>

namespace deploysim::math {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

constexpr double kU2 = 0x1p-106;  // double-double unit roundoff u^2
/// Proven relative error bounds (JMP 2017), in u^2: DWPlusDW 3 (+13u^3), DWTimesDW 4
/// (5 without fma), DWDivDW 15; sqrt (one Newton step on an exact residual) and the
/// double-operand variants are within 4. The checks allow these plus the rounding of the
/// binary128 reference (2^-113 < u^2/100).
constexpr double kAddBound = 3.1 * kU2;
constexpr double kMulBound = 5.1 * kU2;
constexpr double kDivBound = 15.1 * kU2;
constexpr double kSqrtBound = 4.0 * kU2;
/// SinCos: relative to max(|sin|, |cos|) (~25 roundings of u^2 in the series, the square
/// root and the reduction; measured ~3 u^2).
constexpr double kSinCosBound = 1e-31;
/// Identity checks compose a few operations: a handful of u^2.
constexpr double kIdentityTol = 40.0 * kU2;

/// A random normalised double-double with |hi| in [2^(e-1), 2^e) for e in [emin, emax]
/// and lo a random multiple of 2^(e-106) below ulp(hi)/2 in magnitude, so that hi + lo is
/// exact in binary128 (106 bits).
DoubleDouble RandomDD(std::mt19937_64& rng, int emin, int emax) {
  std::uniform_real_distribution<double> unit(0.5, 1.0);
  std::uniform_int_distribution<int> expo(emin, emax);
  std::bernoulli_distribution neg(0.5);
  std::uniform_real_distribution<double> half(-0.5, 0.5);
  const int e = expo(rng);
  double hi = std::ldexp(unit(rng), e);
  if (neg(rng)) hi = -hi;
  const double lo = std::ldexp(std::nearbyint(half(rng) * 0x1p52), e - 106);
  return TwoSum(hi, lo);
}

double Rel(const DoubleDouble& got, const DoubleDouble& want) {
  return std::abs(static_cast<double>(got - want)) / std::abs(want.hi());
}

// ---------------------------------------------------------------------------------------
// (a) Error-free transformations.
// ---------------------------------------------------------------------------------------

TEST(DoubleDoubleTest, TwoSumIsExactByIntegerIdentity) {
  // a = A 2^k, b = B 2^(k-d), |A|, |B| < 2^52, 0 <= d <= 9: every quantity is an integer
  // multiple of g = 2^(k-d) below 2^62 g, so s/g + e/g = A 2^d + B is checked in int64.
  std::mt19937_64 rng(1);
  std::uniform_int_distribution<std::int64_t> mant(-(std::int64_t{1} << 52) + 1,
                                                   (std::int64_t{1} << 52) - 1);
  std::uniform_int_distribution<int> dist(0, 9);
  std::uniform_int_distribution<int> scale(-200, 200);
  for (int i = 0; i < 200000; ++i) {
    const std::int64_t A = mant(rng), B = mant(rng);
    const int d = dist(rng), k = scale(rng);
    const double a = std::ldexp(static_cast<double>(A), k);
    const double b = std::ldexp(static_cast<double>(B), k - d);
    const DoubleDouble s = TwoSum(a, b);
    const DoubleDouble sw = TwoSum(b, a);
    const std::int64_t S = static_cast<std::int64_t>(std::ldexp(s.hi(), d - k));
    const std::int64_t E = static_cast<std::int64_t>(std::ldexp(s.lo(), d - k));
    ASSERT_EQ(S + E, A * (std::int64_t{1} << d) + B) << a << " + " << b;
    ASSERT_EQ(s.hi(), a + b);
    ASSERT_EQ(sw, s);  // symmetric
    ASSERT_LE(std::abs(s.lo()),
              0.5 * (std::nextafter(std::abs(s.hi()), INFINITY) - std::abs(s.hi())));
    if (std::abs(a) >= std::abs(b)) {
      ASSERT_EQ(FastTwoSum(a, b), s);
    }
  }
}

TEST(DoubleDoubleTest, TwoProdIsExactByIntegerIdentity) {
  // a = A 2^ka, b = B 2^kb with |A|, |B| < 2^31: A B < 2^62 is exact in int64, p and e
  // are integer multiples of 2^(ka+kb), and p rounds (A B has up to 62 bits).
  std::mt19937_64 rng(2);
  std::uniform_int_distribution<std::int64_t> mant(-(std::int64_t{1} << 31) + 1,
                                                   (std::int64_t{1} << 31) - 1);
  std::uniform_int_distribution<int> scale(-300, 300);
  int rounded = 0;
  for (int i = 0; i < 200000; ++i) {
    const std::int64_t A = mant(rng), B = mant(rng);
    const int ka = scale(rng), kb = scale(rng);
    const double a = std::ldexp(static_cast<double>(A), ka);
    const double b = std::ldexp(static_cast<double>(B), kb);
    for (const DoubleDouble& p : {TwoProdFma(a, b), TwoProdDekker(a, b), TwoProd(a, b)}) {
      const std::int64_t P = static_cast<std::int64_t>(std::ldexp(p.hi(), -ka - kb));
      const std::int64_t E = static_cast<std::int64_t>(std::ldexp(p.lo(), -ka - kb));
      ASSERT_EQ(P + E, A * B) << a << " * " << b;
      ASSERT_EQ(p.hi(), a * b);
    }
    rounded += TwoProd(a, b).lo() != 0.0;
  }
  EXPECT_GT(rounded, 150000);  // the identity was tested on inexact products
}

TEST(DoubleDoubleTest, FmaAndDekkerProductsAgreeBitForBit) {
  // Two independent exact algorithms (IEEE fma; Dekker's theorem on the split product):
  // the exact error of a product is unique, so they must agree for full 53-bit operands.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> scale(-400, 400);
  for (int i = 0; i < 200000; ++i) {
    const double a = std::ldexp(unit(rng), scale(rng));
    const double b = std::ldexp(unit(rng), scale(rng));
    ASSERT_EQ(TwoProdFma(a, b), TwoProdDekker(a, b)) << a << " * " << b;
  }
  // Known exact product: (2^52 + 1)(2^52 - 1) = 2^104 - 1.
  const DoubleDouble p = TwoProd(0x1p52 + 1.0, 0x1p52 - 1.0);
  EXPECT_EQ(p.hi(), 0x1p104);
  EXPECT_EQ(p.lo(), -1.0);
}

#ifdef __SIZEOF_FLOAT128__
__extension__ typedef __float128 Quad;

Quad ToQuad(const DoubleDouble& x) { return static_cast<Quad>(x.hi()) + x.lo(); }

double AbsRel(const DoubleDouble& got, Quad want) {
  const Quad d = (ToQuad(got) - want) / want;
  return std::abs(static_cast<double>(d));
}

TEST(DoubleDoubleTest, ErrorFreeTransformationsAreExactInBinary128) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> scale(-30, 30);
  for (int i = 0; i < 200000; ++i) {
    const double a = std::ldexp(unit(rng), scale(rng));
    const double b = std::ldexp(unit(rng), scale(rng));  // exponents within 60 bits
    const DoubleDouble s = TwoSum(a, b);
    ASSERT_TRUE(ToQuad(s) == static_cast<Quad>(a) + b) << a << " + " << b;
    const DoubleDouble p = TwoProd(a, b);
    ASSERT_TRUE(ToQuad(p) == static_cast<Quad>(a) * b) << a << " * " << b;
  }
}

TEST(DoubleDoubleTest, ArithmeticWithinProvenBoundsAgainstBinary128) {
  std::mt19937_64 rng(5);
  double worst[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < 200000; ++i) {
    const DoubleDouble x = RandomDD(rng, -20, 20);
    const DoubleDouble y = RandomDD(rng, -20, 20);
    const double yd = RandomDD(rng, -20, 20).hi();
    const Quad qx = ToQuad(x), qy = ToQuad(y);
    const double e[6] = {AbsRel(x + y, qx + qy),  AbsRel(x * y, qx * qy),  AbsRel(x / y, qx / qy),
                         AbsRel(x * yd, qx * yd), AbsRel(x / yd, qx / yd), AbsRel(x + yd, qx + yd)};
    const double bound[6] = {kAddBound, kMulBound, kDivBound, kMulBound, kDivBound, kAddBound};
    for (int k = 0; k < 6; ++k) {
      ASSERT_LE(e[k], bound[k]) << "operation " << k << " x = " << x.hi() << " + " << x.lo()
                                << ", y = " << y.hi() << " + " << y.lo();
      worst[k] = std::max(worst[k], e[k]);
    }
    // Square root of |x| (Newton step on sqrt(hi)): compare its square, exact in binary128.
    const DoubleDouble ax = Abs(x);
    const DoubleDouble r = Sqrt(ax);
    const Quad rq = ToQuad(r);
    ASSERT_LE(std::abs(static_cast<double>((rq * rq - ToQuad(ax)) / ToQuad(ax))), 2 * kSqrtBound);
    // Cancellation: x + (-x + tiny) keeps the relative bound of the (small) result. The
    // reference adds the parts pairwise (each sum exact in binary128, then one rounding).
    const DoubleDouble z = -x + std::ldexp(x.hi(), -70);
    const Quad exact_sum =
        (static_cast<Quad>(x.hi()) + z.hi()) + (static_cast<Quad>(x.lo()) + z.lo());
    ASSERT_LE(AbsRel(x + z, exact_sum), kAddBound)
        << std::hexfloat << x.hi() << " " << x.lo() << " " << z.hi() << " " << z.lo() << " -> "
        << (x + z).hi() << " " << (x + z).lo();
  }
  std::printf(
      "[ measured ] max relative error / u^2: dd+dd %.2f, dd*dd %.2f, dd/dd %.2f, "
      "dd*d %.2f, dd/d %.2f, dd+d %.2f\n",
      worst[0] / kU2, worst[1] / kU2, worst[2] / kU2, worst[3] / kU2, worst[4] / kU2,
      worst[5] / kU2);
}

/// sin and cos in binary128 by their Taylor series after reduction by a binary128 pi/2
/// (an independent evaluation in a wider format; |x| <= 20 here).
void SinCosQuad(Quad x, Quad* s, Quad* c) {
  const Quad pio2 =
      (static_cast<Quad>(0x1.921fb54442d18p+0) + 0x1.1a62633145c07p-54) + -0x1.f1976b7ed8fbcp-110;
  const double kd = std::nearbyint(static_cast<double>(x / pio2));
  const Quad r = x - kd * pio2;
  Quad sr = 0, cr = 0, term_s = r, term_c = 1;
  for (int k = 0; k < 40; ++k) {
    sr += term_s;
    cr += term_c;
    term_s *= -r * r / ((2 * k + 2) * (2 * k + 3));
    term_c *= -r * r / ((2 * k + 1) * (2 * k + 2));
  }
  int q = static_cast<int>(std::fmod(kd, 4.0));
  if (q < 0) q += 4;
  const Quad ss[4] = {sr, cr, -sr, -cr}, cc[4] = {cr, -sr, -cr, sr};
  *s = ss[q];
  *c = cc[q];
}

TEST(DoubleDoubleTest, SinCosAgainstBinary128) {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> wide(-20.0, 20.0);
  std::uniform_real_distribution<double> logs(-30.0, 0.0);
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    DoubleDouble x;
    switch (i % 3) {
      case 0:
        x = RandomDD(rng, -3, 4);
        break;
      case 1: {
        const double hi = std::pow(10.0, logs(rng));
        x = TwoSum(hi, std::ldexp(RandomDD(rng, 0, 0).lo(), std::ilogb(hi) + 1));
        break;
      }
      default:  // near multiples of pi/2 and pi/4
        x = kPiDD * (std::nearbyint(wide(rng)) / 4.0) + std::ldexp(wide(rng), -40);
        break;
    }
    DoubleDouble s, c;
    SinCos(x, &s, &c);
    Quad qs, qc;
    SinCosQuad(ToQuad(x), &qs, &qc);
    const double scale =
        std::max(std::abs(static_cast<double>(qs)), std::abs(static_cast<double>(qc)));
    const double err = std::max(std::abs(static_cast<double>(ToQuad(s) - qs)),
                                std::abs(static_cast<double>(ToQuad(c) - qc))) /
                       scale;
    ASSERT_LE(err, kSinCosBound) << "x = " << x.hi() << " + " << x.lo();
    // Small arguments: relative accuracy of sin itself.
    if (std::abs(x.hi()) < 0.5) {
      ASSERT_LE(AbsRel(s, qs), kSinCosBound) << x.hi();
    }
    worst = std::max(worst, err);
  }
  std::printf("[ measured ] SinCos max error %.3g (%.2f u^2)\n", worst, worst / kU2);
}
TEST(DoubleDoubleTest, SincCosOfSquareAgainstBinary128) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double t_max = std::pow(std::atan(1.0), 2);  // (pi/4)^2, rounded down
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const double f = i % 2 == 0 ? unit(rng) : std::pow(10.0, -30.0 * unit(rng));
    const DoubleDouble t = TwoSum(f * t_max, std::ldexp(unit(rng) - 0.5, -60) * f * t_max);
    DoubleDouble sinc, c;
    SincCosOfSquare(t, &sinc, &c);
    // Reference from the binary128 series of sin r and cos r at r = sqrt(t).
    Quad r = std::sqrt(static_cast<double>(t));  // Newton on r^2 = t in binary128
    for (int k = 0; k < 3; ++k) r = (r + ToQuad(t) / r) / 2;
    Quad qs, qc;
    SinCosQuad(r, &qs, &qc);
    const double err = std::max(AbsRel(sinc, qs / r), AbsRel(c, qc));
    ASSERT_LE(err, kSinCosBound) << "t = " << t.hi();
    worst = std::max(worst, err);
  }
  std::printf("[ measured ] SincCosOfSquare max relative error %.3g (%.2f u^2)\n", worst,
              worst / kU2);
}
#endif  // __SIZEOF_FLOAT128__

// ---------------------------------------------------------------------------------------
// (b) Identities, on every platform.
// ---------------------------------------------------------------------------------------

TEST(DoubleDoubleTest, ExactIntegerResults) {
  const DoubleDouble n = TwoProd(0x1p52 + 1.0, 0x1p52 - 1.0);  // 2^104 - 1
  const DoubleDouble q = n / (0x1p52 + 1.0);
  EXPECT_LE(std::abs(static_cast<double>(q - (0x1p52 - 1.0))), kDivBound * 0x1p52);
  EXPECT_EQ(n + 1.0, DoubleDouble(0x1p104));
  EXPECT_EQ((n + 1.0) - n, DoubleDouble(1.0));  // 2^104 - (2^104 - 1), far below ulp(2^104)
  // 1/3 carries 106 bits: 3 * (1/3) = 1 to u^2, while double gives 1 only by luck.
  const DoubleDouble third = DoubleDouble(1.0) / 3.0;
  EXPECT_LE(std::abs(static_cast<double>(third * 3.0 - 1.0)), kMulBound + kDivBound);
  EXPECT_NE(third.lo(), 0.0);
  EXPECT_EQ(Sqrt(DoubleDouble(0x1p104) - 0x1p53 + 1.0), DoubleDouble(0x1p52 - 1.0));  // (2^52-1)^2
  EXPECT_EQ(Sqrt(DoubleDouble(0.0)), DoubleDouble(0.0));
  EXPECT_TRUE(std::isnan(Sqrt(DoubleDouble(-1.0)).hi()));
}

TEST(DoubleDoubleTest, RoundTripsHoldToAFewUlps) {
  std::mt19937_64 rng(7);
  double worst = 0.0;
  for (int i = 0; i < 100000; ++i) {
    const DoubleDouble x = RandomDD(rng, -30, 30);
    const DoubleDouble y = RandomDD(rng, -30, 30);
    const double scale = std::max(std::abs(x.hi()), std::abs(y.hi()));
    const double errs[4] = {
        std::abs(static_cast<double>((x + y) - y - x)) / scale,
        Rel((x * y) / y, x),
        Rel((x / y) * y, x),
        Rel(Square(Sqrt(Abs(x))), Abs(x)),
    };
    for (double e : errs) {
      ASSERT_LE(e, kIdentityTol) << x.hi() << " " << y.hi();
      worst = std::max(worst, e);
    }
    ASSERT_EQ(x < y, x.hi() < y.hi() || (x.hi() == y.hi() && x.lo() < y.lo()));
    ASSERT_TRUE(x - x == DoubleDouble(0.0));
  }
  std::printf("[ measured ] round trips: max %.2f u^2\n", worst / kU2);
}

TEST(DoubleDoubleTest, OrderIsThatOfTheValues) {
  const DoubleDouble one(1.0);
  const DoubleDouble above = TwoSum(1.0, 0x1p-80);
  const DoubleDouble below = TwoSum(1.0, -0x1p-80);
  EXPECT_LT(below, one);
  EXPECT_LT(one, above);
  EXPECT_GT(above, below);
  EXPECT_LE(one, one);
  EXPECT_GE(one, below);
  EXPECT_EQ(static_cast<double>(above), 1.0);
  EXPECT_NE(above, one);
  EXPECT_EQ(Abs(-above), above);
}

TEST(DoubleDoubleTest, SinCosIdentitiesAndKnownValues) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-12.0, 12.0);
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const DoubleDouble x = TwoSum(u(rng), std::ldexp(u(rng), -60));
    DoubleDouble s, c, s2, c2;
    SinCos(x, &s, &c);
    SinCos(x * 2.0, &s2, &c2);
    const double errs[3] = {
        std::abs(static_cast<double>(Square(s) + Square(c) - 1.0)),
        std::abs(static_cast<double>(s2 - 2.0 * s * c)),
        std::abs(static_cast<double>(c2 - (Square(c) - Square(s)))),
    };
    for (double e : errs) {
      ASSERT_LE(e, kSinCosBound * 4) << x.hi();
      worst = std::max(worst, e);
    }
  }
  std::printf("[ measured ] sin^2 + cos^2 - 1, double angles: max %.3g\n", worst);
  // Known values at double-double multiples of pi (|pi - kPiDD| < 3e-33).
  DoubleDouble s, c;
  SinCos(kPiDD / 6.0, &s, &c);
  EXPECT_LE(std::abs(static_cast<double>(s - 0.5)), kSinCosBound);
  EXPECT_LE(std::abs(static_cast<double>(Square(c) - 0.75)), kSinCosBound);
  SinCos(kPiDD / 4.0, &s, &c);
  EXPECT_LE(std::abs(static_cast<double>(s - Sqrt(DoubleDouble(0.5)))), kSinCosBound);
  EXPECT_LE(std::abs(static_cast<double>(c - Sqrt(DoubleDouble(0.5)))), kSinCosBound);
  SinCos(kPiDD / 3.0, &s, &c);
  EXPECT_LE(std::abs(static_cast<double>(c - 0.5)), kSinCosBound);
  // sin(pi_dd) = sin(pi - pi_dd) = pi - pi_dd = -3.0e-33 (the third part of pi): the
  // reduction resolves what double-double pi leaves out.
  SinCos(kPiDD, &s, &c);
  constexpr double kPiMinusPiDD = -0x1.f1976b7ed8fbcp-109;
  EXPECT_NEAR(s.hi(), kPiMinusPiDD, 1e-12 * std::abs(kPiMinusPiDD));
  EXPECT_LE(std::abs(static_cast<double>(c + 1.0)), kSinCosBound);
  SinCos(DoubleDouble(0.0), &s, &c);
  EXPECT_EQ(s, DoubleDouble(0.0));
  EXPECT_EQ(c, DoubleDouble(1.0));
  // Tiny arguments: sin x = x - x^3/6 exactly to double-double rounding.
  const DoubleDouble t(1e-9);
  SinCos(t, &s, &c);
  EXPECT_LE(Rel(s, t - Square(t) * t / 6.0), 2 * kU2);
  SinCos(DoubleDouble(std::nan("")), &s, &c);
  EXPECT_TRUE(std::isnan(s.hi()) && std::isnan(c.hi()));
  // SincCosOfSquare: t sinc^2 + cos^2 = sin^2 + cos^2 = 1 (exact identity in reals).
  std::uniform_real_distribution<double> r(0.0, 0.78);
  double worst_sinc = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const DoubleDouble t2 = Square(DoubleDouble(r(rng)));
    DoubleDouble sinc, cs;
    SincCosOfSquare(t2, &sinc, &cs);
    const double e = std::abs(static_cast<double>(t2 * Square(sinc) + Square(cs) - 1.0));
    ASSERT_LE(e, kSinCosBound * 4) << t2.hi();
    worst_sinc = std::max(worst_sinc, e);
  }
  SincCosOfSquare(DoubleDouble(0.0), &s, &c);
  EXPECT_EQ(s, DoubleDouble(1.0));
  EXPECT_EQ(c, DoubleDouble(1.0));
  std::printf("[ measured ] SincCosOfSquare: t sinc^2 + cos^2 - 1 max %.3g\n", worst_sinc);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::math
