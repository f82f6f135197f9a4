// The piecewise Chebyshev interpolant (analysis/chebyshev.h): polynomials up to its degree
// reproduced with their own degree, smooth functions to a few ulp of their scale, steep ones
// split into pieces, values' rounding noise accepted up to the caller's bound, bad input.

#include "deploysim/analysis/chebyshev.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace deploysim::analysis {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

/// prod_{k < degree} (t - r_k), roots r_k = 0.3 + 0.17 k spread over [-1, 2].
double RootPolynomial(int degree, double t) {
  double p = 1.0;
  for (int k = 0; k < degree; ++k) p *= t - (0.3 + 0.17 * k);
  return p;
}

/// A bound on |RootPolynomial| over [-1, 2]: the product of the factors' largest values.
double RootPolynomialScale(int degree) {
  double s = 1.0;
  for (int k = 0; k < degree; ++k) {
    const double r = 0.3 + 0.17 * k;
    s *= std::max(std::abs(-1.0 - r), std::abs(2.0 - r));
  }
  return s;
}

// A polynomial of degree n is its own Chebyshev series: the fit keeps n + 1 coefficients
// (max_degree == n), with one piece of 17 values while the 4 tail coefficients of the
// start degree 16 vanish (n <= 12), else 33. Against the polynomial, at 3001 points of
// [-1, 2]: measured at most 1.5e-15 of max |p| (n = 12); bound 8e-15.
TEST(ChebyshevFitTest, PolynomialsAreReproducedWithTheirOwnDegree) {
  for (int n : {0, 1, 3, 7, 12, 13, 20}) {
    auto f = [n](double t, double* out) { out[0] = RootPolynomial(n, t); };
    ChebyshevFit fit;
    ASSERT_TRUE(fit.Build(f, -1.0, 2.0, {RootPolynomialScale(n)}, {0.0}, 1000)) << n;
    EXPECT_EQ(fit.pieces(), 1u) << n;
    EXPECT_EQ(fit.max_degree(), n) << n;
    EXPECT_EQ(fit.evaluations(), n <= 12 ? 17u : 33u) << n;
    double err = 0.0, peak = 0.0;
    for (int i = 0; i <= 3000; ++i) {
      const double t = -1.0 + 1e-3 * i;
      double v;
      fit.Evaluate(t, &v);
      err = std::max(err, std::abs(v - RootPolynomial(n, t)));
      peak = std::max(peak, std::abs(RootPolynomial(n, t)));
    }
    std::printf("degree %d: %zu values, error %.2e of max |p| %.3g\n", n, fit.evaluations(),
                err / peak, peak);
    EXPECT_LE(err, 8e-15 * peak) << n;
  }
}

// Three smooth components fitted together on [0, 2], one piece; each within 3e-15 of its
// scale at 20001 points (measured exp 6.2e-15 = 0.84e-15 e^2, cos(3t) 1.1e-15, log(1 + t)
// 1.3e-15 = 1.2e-15 log 3), ascending and descending; outside [a, b] the ends' values.
TEST(ChebyshevFitTest, SmoothComponentsAgreeToAFewUlpOfTheirScale) {
  auto f = [](double t, double* out) {
    out[0] = std::exp(t);
    out[1] = std::cos(3.0 * t);
    out[2] = std::log1p(t);
  };
  const std::vector<double> scale = {std::exp(2.0), 1.0, std::log(3.0)};
  ChebyshevFit fit;
  ASSERT_TRUE(fit.Build(f, 0.0, 2.0, scale, {0.0, 0.0, 0.0}, 1000));
  EXPECT_EQ(fit.dim(), 3u);
  EXPECT_EQ(fit.pieces(), 1u);
  EXPECT_LE(fit.max_degree(), 32);
  double err[3] = {0.0, 0.0, 0.0};
  auto check = [&](int i) {
    const double t = 1e-4 * i;
    double v[3], ref[3];
    fit.Evaluate(t, v);
    f(t, ref);
    for (int k = 0; k < 3; ++k) err[k] = std::max(err[k], std::abs(v[k] - ref[k]) / scale[k]);
  };
  for (int i = 0; i <= 20000; ++i) check(i);
  for (int i = 20000; i >= 0; i -= 7) check(i);
  std::printf("exp %.2e, cos %.2e, log1p %.2e of their scales\n", err[0], err[1], err[2]);
  for (int k = 0; k < 3; ++k) EXPECT_LE(err[k], 3e-15) << k;
  double out[3], end[3];
  fit.Evaluate(5.0, out);
  fit.Evaluate(2.0, end);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(out[k], end[k]);
  fit.Evaluate(-1.0, out);
  fit.Evaluate(0.0, end);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(out[k], end[k]);
}

// Runge's function 1/(1 + 25 t^2) on [-1, 1]: its coefficients decay as 1.22^-k, so
// degree 64 does not reach rounding and the interval is halved; measured 2 pieces of
// degree up to 54 and an error of 1.2e-15 at 20001 points (bound 4e-15).
TEST(ChebyshevFitTest, RungeFunctionIsSplitIntoPieces) {
  auto f = [](double t, double* out) { out[0] = 1.0 / (1.0 + 25.0 * t * t); };
  ChebyshevFit fit;
  ASSERT_TRUE(fit.Build(f, -1.0, 1.0, {1.0}, {0.0}, 100000));
  EXPECT_GE(fit.pieces(), 2u);
  EXPECT_LE(fit.max_degree(), ChebyshevFit::kMaxDegree);
  double err = 0.0;
  for (int i = 0; i <= 20000; ++i) {
    const double t = -1.0 + 1e-4 * i;
    double v, ref;
    fit.Evaluate(t, &v);
    f(t, &ref);
    err = std::max(err, std::abs(v - ref));
  }
  std::printf("Runge: %zu pieces, degree %d, %zu values, error %.2e\n", fit.pieces(),
              fit.max_degree(), fit.evaluations(), err);
  EXPECT_LE(err, 4e-15);
}

/// A deterministic noise in [-1e-12, 1e-12) from the bits of t (a SplitMix-style hash).
double Noise(double t) {
  std::uint64_t h;
  std::memcpy(&h, &t, sizeof h);
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return (static_cast<double>(h >> 11) * 0x1.0p-53 - 0.5) * 2e-12;
}

// Values that carry a noise of 1e-12: with that bound given the coefficients' plateau is
// accepted (one piece, measured 33 values, error against the clean function 1.3e-12, the
// noise's own size; bound 3e-12); with no bound no degree reaches it and the fit gives up.
TEST(ChebyshevFitTest, NoisyValuesAreAcceptedOnlyUpToTheCallersBound) {
  auto f = [](double t, double* out) { out[0] = std::sin(t) + Noise(t); };
  ChebyshevFit fit;
  ASSERT_TRUE(fit.Build(f, 0.0, 1.0, {1.0}, {1e-12}, 5000));
  EXPECT_EQ(fit.pieces(), 1u);
  double err = 0.0;
  for (int i = 0; i <= 10000; ++i) {
    const double t = 1e-4 * i;
    double v;
    fit.Evaluate(t, &v);
    err = std::max(err, std::abs(v - std::sin(t)));
  }
  std::printf("noise 1e-12: %zu values, error %.2e\n", fit.evaluations(), err);
  EXPECT_LE(err, 3e-12);
  EXPECT_FALSE(fit.Build(f, 0.0, 1.0, {1.0}, {0.0}, 5000));
  EXPECT_FALSE(fit.valid());
}

// Moved from the exact stepper's dense output tests (tests/analysis/exact_flow_test.cpp).
TEST(ChebyshevFitTest, SteepPulseIsSplitAndAccurate) {
  // A sech pulse of width 1e-3 in [0, 10]: one polynomial of degree 64 cannot hold it.
  auto f = [](double t, double* out) {
    out[0] = 1.0 / std::cosh(t * 1e3);
    out[1] = std::tanh(t * 1e3);
  };
  ChebyshevFit fit;
  ASSERT_TRUE(fit.Build(f, -3.0, 7.0, {1.0, 1.0}, {0.0, 0.0}, 100000));
  EXPECT_GT(fit.pieces(), 4u);
  EXPECT_LE(fit.max_degree(), ChebyshevFit::kMaxDegree);
  double err = 0.0;
  for (int i = 0; i <= 100000; ++i) {
    const double t = -3.0 + 1e-4 * i;
    double v[2], ref[2];
    fit.Evaluate(t, v);
    f(t, ref);
    err = std::max({err, std::abs(v[0] - ref[0]), std::abs(v[1] - ref[1])});
  }
  EXPECT_LT(err, 2e-15);  // measured 4.4e-16
  // A budget too small for the pulse: no fit.
  EXPECT_FALSE(fit.Build(f, -3.0, 7.0, {1.0, 1.0}, {0.0, 0.0}, 100));
  EXPECT_FALSE(fit.valid());
}

TEST(ChebyshevFitTest, SmoothFunctionNeedsOnePieceOfLowDegree) {
  auto f = [](double t, double* out) { out[0] = std::sin(t); };
  ChebyshevFit fit;
  ASSERT_TRUE(fit.Build(f, 0.0, 1.0, {1.0}, {0.0}, 1000));
  EXPECT_EQ(fit.pieces(), 1u);
  EXPECT_LE(fit.max_degree(), 16);
  EXPECT_EQ(fit.evaluations(), 17u);
  double v;
  fit.Evaluate(1.0, &v);
  EXPECT_NEAR(v, std::sin(1.0), 1e-15);
  EXPECT_THROW(fit.Build(f, 1.0, 1.0, {1.0}, {0.0}, 1000), std::invalid_argument);
  EXPECT_THROW(fit.Build(f, 0.0, 1.0, {0.0}, {0.0}, 1000), std::invalid_argument);
  EXPECT_THROW(fit.Build(f, 0.0, 1.0, {1.0}, {}, 1000), std::invalid_argument);
}

TEST(ChebyshevFitTest, BadArgumentsAreRefused) {
  auto f = [](double t, double* out) { out[0] = t; };
  ChebyshevFit fit;
  EXPECT_THROW(fit.Build(f, 2.0, 1.0, {1.0}, {0.0}, 1000), std::invalid_argument);
  EXPECT_THROW(fit.Build(f, 0.0, NAN, {1.0}, {0.0}, 1000), std::invalid_argument);
  EXPECT_THROW(
      fit.Build(f, 0.0, 1.0, std::vector<double>(17, 1.0), std::vector<double>(17, 0.0), 1000),
      std::invalid_argument);
  EXPECT_THROW(fit.Build(f, 0.0, 1.0, {-1.0}, {0.0}, 1000), std::invalid_argument);
  EXPECT_THROW(fit.Build(f, 0.0, 1.0, {INFINITY}, {0.0}, 1000), std::invalid_argument);
  EXPECT_THROW(fit.Build(f, 0.0, 1.0, {1.0}, {-1e-12}, 1000), std::invalid_argument);
  EXPECT_THROW(fit.Build(f, 0.0, 1.0, {1.0}, {NAN}, 1000), std::invalid_argument);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::analysis
