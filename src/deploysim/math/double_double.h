#pragma once

/// Double-double arithmetic: a value is the unevaluated sum hi + lo of two doubles with
/// |lo| <= ulp(hi)/2 (hi = fl(hi + lo)), about 106 significant bits (unit roundoff
/// u^2 = 2^-106 ~ 1.2e-32), the exponent range of double. It replaces the platform's
/// extended floating type wherever double is not enough (docs/design.md 2.3 and 6, STYLE.md):
/// x87 extended precision exists only on x86; with MSVC and on Apple silicon that type is
/// plain double, and on aarch64 Linux it is a software binary128 (correct, ~50x slower).
///
/// Building blocks, the error-free transformations (exact for finite results without
/// overflow, in IEEE binary64 with round-to-nearest):
///   TwoSum      s + e = a + b           Knuth, TAOCP vol. 2 (3rd ed. 1998) 4.2.2 Thm B;
///   FastTwoSum  s + e = a + b, |a|>=|b| Dekker, Numer. Math. 18 (1971) 224-242;
///   TwoProd     p + e = a * b           by std::fma (e = fma(a, b, -p)); Dekker's split
///                                        product (Veltkamp splitting) as the alternative.
/// The arithmetic follows Joldes, Muller, Popescu, "Tight and rigorous error bounds for
/// basic building blocks of double-word arithmetic", ACM TOMS 44(2) 2017 (algorithm
/// numbers below; relative error bounds in u = 2^-53), which proves the bounds of the
/// QD library's operations (Hida, Li, Bailey, "Algorithms for quad-double precision
/// floating point arithmetic", ARITH-15, 2001); see also Shewchuk, Discrete Comput. Geom.
/// 18 (1997) 305-363, for expansions. Sqrt is one Newton (Heron) step on sqrt(hi) with an
/// exact residual (Karp and Markstein, ACM TOMS 23(4) 1997). SinCos is in double_double.cc.
///
/// Why a unit of our own: Debian's libqd-dev (QD 2.3.23) provides dd_real, but as a
/// compiled shared library (libqd0v5) that every build would have to install and link for
/// its target (the aarch64 cross build needs libqd-dev:arm64; macOS and MSVC builds need
/// it from elsewhere), whose x86 builds need the x87 control word set around every use
/// (fpu_fix_start); there is no header-only double-double package in Debian. deploysim
/// needs only the few operations below: this header (plus SinCos) depends on nothing but
/// <cmath>, compiles wherever binary64 with round-to-nearest is the evaluation format
/// (x86-64 SSE2, aarch64, MSVC), inlines into the hot loops (the RKMK attitude carry, the
/// Landen recursion), and its bounds are those of the cited paper. Value-changing optimisations
/// (-ffast-math, -fassociative-math) break error-free transformations: never build with them.
/// Contraction of a*b+c into fma (-ffp-contract) is harmless here: no transformation
/// below relies on a rounded product feeding an addition in the same expression.

#include <cfloat>
#include <cmath>

#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD != 0 && FLT_EVAL_METHOD != -1
#error "double-double arithmetic needs double evaluated in binary64 (no x87 excess precision)"
#endif

namespace deploysim::math {

/// A double-double number hi + lo. Class invariant: |lo| <= ulp(hi)/2, i.e. hi is the
/// double nearest to the value (so comparisons are lexicographic and static_cast<double>
/// returns hi). Implicitly constructible from double (exactly).
class DoubleDouble {
 public:
  constexpr DoubleDouble() = default;
  // NOLINTNEXTLINE(google-explicit-constructor): exact, a widening conversion.
  constexpr DoubleDouble(double x) : hi_(x) {}

  /// Unchecked: the caller guarantees the invariant (|lo| <= ulp(hi)/2), e.g. for
  /// constants written as hexadecimal pairs. Use TwoSum(a, b) for arbitrary a, b.
  static constexpr DoubleDouble FromParts(double hi, double lo) {
    DoubleDouble r;
    r.hi_ = hi;
    r.lo_ = lo;
    return r;
  }

  constexpr double hi() const { return hi_; }
  constexpr double lo() const { return lo_; }
  /// The double nearest to the value (hi).
  explicit constexpr operator double() const { return hi_; }

  constexpr DoubleDouble operator-() const { return FromParts(-hi_, -lo_); }

  inline DoubleDouble& operator+=(const DoubleDouble& y);
  inline DoubleDouble& operator-=(const DoubleDouble& y);
  inline DoubleDouble& operator*=(const DoubleDouble& y);
  inline DoubleDouble& operator/=(const DoubleDouble& y);

 private:
  double hi_ = 0.0;
  double lo_ = 0.0;
};

/// 2^-104: the relative error bounds below are small multiples of 2^-106; this is the
/// precision a double-double result can be relied on to (like numeric_limits::epsilon).
inline constexpr double kDoubleDoubleEps = 0x1p-104;

/// pi to double-double precision (hi + lo = pi - 2.9e-33).
inline constexpr DoubleDouble kPiDD =
    DoubleDouble::FromParts(0x1.921fb54442d18p+1, 0x1.1a62633145c07p-53);

// ---------------------------------------------------------------------------------------
// Error-free transformations.
// ---------------------------------------------------------------------------------------

/// s = fl(a + b) and the exact error e: s + e = a + b, |e| <= ulp(s)/2 (Knuth; Moller
/// 1965). 6 flops, no branch, no precondition.
inline DoubleDouble TwoSum(double a, double b) {
  const double s = a + b;
  const double bb = s - a;
  const double e = (a - (s - bb)) + (b - bb);
  return DoubleDouble::FromParts(s, e);
}

/// As TwoSum, for |a| >= |b| (or a = 0); 3 flops (Dekker 1971).
inline DoubleDouble FastTwoSum(double a, double b) {
  const double s = a + b;
  const double e = b - (s - a);
  return DoubleDouble::FromParts(s, e);
}

/// p = fl(a b) and the exact error e = fma(a, b, -p): p + e = a b (when no underflow).
inline DoubleDouble TwoProdFma(double a, double b) {
  const double p = a * b;
  return DoubleDouble::FromParts(p, std::fma(a, b, -p));
}

/// The same by Dekker's product with Veltkamp's splitting (17 flops, no fma); exact for
/// |a|, |b| < 2^995 (the splitting multiplies by 2^27 + 1) and no underflow.
inline DoubleDouble TwoProdDekker(double a, double b) {
  constexpr double kSplitter = 134217729.0;  // 2^27 + 1
  const double ta = kSplitter * a;
  const double ah = ta - (ta - a);
  const double al = a - ah;
  const double tb = kSplitter * b;
  const double bh = tb - (tb - b);
  const double bl = b - bh;
  const double p = a * b;
  return DoubleDouble::FromParts(p, ((ah * bh - p) + ah * bl + al * bh) + al * bl);
}

/// a * b as an exact double-double. std::fma is exact everywhere; where it is a single
/// instruction (FP_FAST_FMA: aarch64, x86-64 with FMA3 enabled) it is used, else a call to
/// the C library's fma would cost more than Dekker's 17 inline flops, equally exact.
inline DoubleDouble TwoProd(double a, double b) {
#ifdef FP_FAST_FMA
  return TwoProdFma(a, b);
#else
  return TwoProdDekker(a, b);
#endif
}

namespace detail {
/// a b + c, fused where that is one instruction. Used only where the bound does not need
/// the fusion (the algorithms' bounds grow by at most u^2 without it).
inline double MulAdd(double a, double b, double c) {
#ifdef FP_FAST_FMA
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}
}  // namespace detail

// ---------------------------------------------------------------------------------------
// Arithmetic (Joldes, Muller, Popescu 2017; relative error bounds in u = 2^-53).
// ---------------------------------------------------------------------------------------

/// x + y, y a double (Algorithm 4, DWPlusFP): error <= 2 u^2.
inline DoubleDouble operator+(const DoubleDouble& x, double y) {
  const DoubleDouble s = TwoSum(x.hi(), y);
  return FastTwoSum(s.hi(), x.lo() + s.lo());
}
inline DoubleDouble operator+(double x, const DoubleDouble& y) { return y + x; }

/// x + y (Algorithm 6, AccurateDWPlusDW): error <= 3 u^2 + 13 u^3, also under
/// cancellation.
inline DoubleDouble operator+(const DoubleDouble& x, const DoubleDouble& y) {
  const DoubleDouble s = TwoSum(x.hi(), y.hi());
  const DoubleDouble t = TwoSum(x.lo(), y.lo());
  const DoubleDouble v = FastTwoSum(s.hi(), s.lo() + t.hi());
  return FastTwoSum(v.hi(), t.lo() + v.lo());
}

inline DoubleDouble operator-(const DoubleDouble& x, double y) { return x + (-y); }
inline DoubleDouble operator-(double x, const DoubleDouble& y) { return x + (-y); }
inline DoubleDouble operator-(const DoubleDouble& x, const DoubleDouble& y) { return x + (-y); }

/// x * y, y a double (Algorithm 9, DWTimesFP3): error <= 2 u^2.
inline DoubleDouble operator*(const DoubleDouble& x, double y) {
  const DoubleDouble c = TwoProd(x.hi(), y);
  return FastTwoSum(c.hi(), detail::MulAdd(x.lo(), y, c.lo()));
}
inline DoubleDouble operator*(double x, const DoubleDouble& y) { return y * x; }

/// x * y (Algorithm 12, DWTimesDW3): error <= 4 u^2.
inline DoubleDouble operator*(const DoubleDouble& x, const DoubleDouble& y) {
  const DoubleDouble c = TwoProd(x.hi(), y.hi());
  const double tl1 = detail::MulAdd(x.hi(), y.lo(), x.lo() * y.lo());
  const double cl2 = detail::MulAdd(x.lo(), y.hi(), tl1);
  return FastTwoSum(c.hi(), c.lo() + cl2);
}

/// x / y, y a double (Algorithm 15, DWDivFP3): error <= 3 u^2.
inline DoubleDouble operator/(const DoubleDouble& x, double y) {
  const double th = x.hi() / y;
  const DoubleDouble p = TwoProd(th, y);
  const double d = ((x.hi() - p.hi()) - p.lo()) + x.lo();
  return FastTwoSum(th, d / y);
}

/// x / y (Algorithm 17, DWDivDW2): error <= 15 u^2.
inline DoubleDouble operator/(const DoubleDouble& x, const DoubleDouble& y) {
  const double th = x.hi() / y.hi();
  const DoubleDouble r = y * th;
  const double d = (x.hi() - r.hi()) + (x.lo() - r.lo());
  return FastTwoSum(th, d / y.hi());
}
inline DoubleDouble operator/(double x, const DoubleDouble& y) { return DoubleDouble(x) / y; }

inline DoubleDouble& DoubleDouble::operator+=(const DoubleDouble& y) { return *this = *this + y; }
inline DoubleDouble& DoubleDouble::operator-=(const DoubleDouble& y) { return *this = *this - y; }
inline DoubleDouble& DoubleDouble::operator*=(const DoubleDouble& y) { return *this = *this * y; }
inline DoubleDouble& DoubleDouble::operator/=(const DoubleDouble& y) { return *this = *this / y; }

/// x^2, error <= 4 u^2 (one fma fewer than x * x).
inline DoubleDouble Square(const DoubleDouble& x) {
  const DoubleDouble c = TwoProd(x.hi(), x.hi());
  return FastTwoSum(c.hi(), c.lo() + 2.0 * x.hi() * x.lo());
}

/// sqrt(x) for x >= 0: s = sqrt(hi), then one Newton step with the exact residual
/// x - s^2 (TwoProd); error ~ 3 u^2. NaN for x < 0; x = 0 and +inf pass through.
inline DoubleDouble Sqrt(const DoubleDouble& x) {
  const double s = std::sqrt(x.hi());
  if (!(s > 0.0) || !std::isfinite(s)) return s;
  const DoubleDouble p = TwoProd(s, s);
  const double r = ((x.hi() - p.hi()) - p.lo()) + x.lo();  // x.hi - p.hi is exact
  return FastTwoSum(s, r / (2.0 * s));
}

inline DoubleDouble Abs(const DoubleDouble& x) { return x.hi() < 0.0 ? -x : x; }

/// sin(x) and cos(x). Reduction by multiples of pi/2 with a three-part pi/2 (Cody and
/// Waite), then the Taylor series of sin and cos on |r| <= pi/4 (SincCosOfSquare of r^2)
/// with as many terms as |r| needs (Horner in r^2, the small terms in double). Error ~ 1e-31
/// relative to max(|sin|, |cos|) for |x| <= 2^20; the reduction's absolute error grows like |x|
/// 2^-160 beyond. Non-finite x gives NaN.
void SinCos(const DoubleDouble& x, DoubleDouble* sin_x, DoubleDouble* cos_x);

/// For 0 <= t <= (pi/4)^2: sinc = sin(sqrt t) / sqrt t and cos = cos(sqrt t), from their
/// Taylor series in t (Horner, two independent chains), with neither square root nor
/// division: what a rotation exponential needs, (cos(a/2), sin(a/2)/a v) with t = |v|^2/4.
/// Error ~1e-31 relative.
void SincCosOfSquare(const DoubleDouble& t, DoubleDouble* sinc, DoubleDouble* cos);

inline bool operator==(const DoubleDouble& x, const DoubleDouble& y) {
  return x.hi() == y.hi() && x.lo() == y.lo();
}
inline bool operator!=(const DoubleDouble& x, const DoubleDouble& y) { return !(x == y); }
inline bool operator<(const DoubleDouble& x, const DoubleDouble& y) {
  return x.hi() < y.hi() || (x.hi() == y.hi() && x.lo() < y.lo());
}
inline bool operator>(const DoubleDouble& x, const DoubleDouble& y) { return y < x; }
inline bool operator<=(const DoubleDouble& x, const DoubleDouble& y) { return x < y || x == y; }
inline bool operator>=(const DoubleDouble& x, const DoubleDouble& y) { return y <= x; }

}  // namespace deploysim::math
