// The nutation envelope and its exponential fit on signals whose rate is known: the
// largest sample per window of a steady spin's nutation, and the Hann-weighted mean square
// of a nutation about a periodic orbit, whose magnitude the orbit modulates.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "deploysim/analysis/motion_outcome.h"

namespace deploysim::analysis {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

constexpr double kTwoPi = 6.283185307179586;

/// |tilt| of a nutation that grows at sigma with frequency w on an ellipse (axes 1 and
/// 0.4), modulated by an orbit of period T (a 30 % ripple and its second harmonic).
double OrbitNutation(double t, double sigma, double w, double T) {
  const double x = std::cos(w * t), y = 0.4 * std::sin(w * t);
  const double ripple = 1.0 + 0.3 * std::sin(kTwoPi * t / T) + 0.1 * std::cos(2.0 * kTwoPi * t / T);
  return 1e-5 * std::exp(sigma * t) * std::hypot(x, y) * ripple;
}

// About a periodic orbit the largest sample per window jitters with the beat of the
// nutation and the orbit; the mean square per nutation period does not. Decaying and
// growing, the nutation slower and faster than the orbit, or not oscillating: the fitted
// rate within 5e-4 of sigma (measured 1.8e-4, 1.6e-7, 8.8e-5, 5.2e-7), where the windows'
// maxima are off by 4.5e-3, 4.2e-4, 2.6e-2 and 6.1e-3.
TEST(EnvelopeTest, MeanSquareOverAPeriodicOrbitFitsTheRate) {
  struct Case {
    double sigma, w, T;
  };
  for (const Case c : {Case{-4e-4, 0.09, 9.05}, Case{0.0046, 0.26, 1.58},
                       Case{-1.2e-4, 0.042, 6.84}, Case{0.04, 0.0, 5.9}}) {
    const double window = c.w > 0.0 ? kTwoPi / c.w : 2.0 * c.T;
    const double until = std::min(1200.0, 5.0 / std::abs(c.sigma));
    EnvelopeTracker ms, mx;
    ms.ResetMeanSquare(window);
    mx.Reset(window);
    for (double t = 0.0; t <= until; t += 0.1) {
      const double nu = OrbitNutation(t, c.sigma, c.w, c.T);
      ms.Add(t, nu);
      mx.Add(t, nu);
    }
    const ExponentialFit a = FitEnvelope(ms.peaks(), kFitFloor, kFitCeiling, 0.0);
    const ExponentialFit b = FitEnvelope(mx.peaks(), kFitFloor, kFitCeiling, 0.0);
    ASSERT_TRUE(a.valid);
    std::printf(
        "sigma %+.2e, w %.3g, T %.3g: mean square %+.2e (+- %.1e, %d windows), "
        "maxima %+.2e\n",
        c.sigma, c.w, c.T, a.rate / c.sigma - 1.0, a.rate_uncertainty / std::abs(c.sigma), a.points,
        b.valid ? b.rate / c.sigma - 1.0 : NAN);
    EXPECT_NEAR(a.rate, c.sigma, 5e-4 * std::abs(c.sigma));
    EXPECT_GE(a.points, 11);
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::analysis
