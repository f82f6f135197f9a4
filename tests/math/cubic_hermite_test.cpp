// math::CubicHermiteMinimum: the minimum of the cubic through two points with their
// slopes, on the closed interval.

#include "deploysim/math/cubic_hermite.h"

#include <gtest/gtest.h>

#include <cmath>

namespace deploysim::math {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

// A cubic is its own Hermite interpolant: the minimum is the cubic's.
TEST(CubicHermiteMinimumTest, IsExactForACubic) {
  // p(t) = (t - 1)^2 (t + 2) on [0, 2]: interior minimum 0 at t = 1.
  auto p = [](double t) { return (t - 1.0) * (t - 1.0) * (t + 2.0); };
  auto dp = [](double t) { return 2.0 * (t - 1.0) * (t + 2.0) + (t - 1.0) * (t - 1.0); };
  EXPECT_NEAR(CubicHermiteMinimum(0.0, p(0.0), dp(0.0), 2.0, p(2.0), dp(2.0)), 0.0, 1e-15);
  // Shifted in time and scaled: the same shape on [10, 10.002].
  const double h = 0.002;
  auto q = [&](double t) { return p((t - 10.0) / h * 2.0); };
  auto dq = [&](double t) { return dp((t - 10.0) / h * 2.0) * 2.0 / h; };
  EXPECT_NEAR(CubicHermiteMinimum(10.0, q(10.0), dq(10.0), 10.0 + h, q(10.0 + h), dq(10.0 + h)),
              0.0, 1e-12);
}

TEST(CubicHermiteMinimumTest, EndsCountWhenTheCubicIsMonotone) {
  // p(t) = t^3 + t: increasing, minimum at the left end.
  EXPECT_EQ(CubicHermiteMinimum(0.0, 0.0, 1.0, 1.0, 2.0, 4.0), 0.0);
  // Decreasing: at the right end.
  EXPECT_EQ(CubicHermiteMinimum(0.0, 2.0, -4.0, 1.0, 0.0, -1.0), 0.0);
}

TEST(CubicHermiteMinimumTest, QuadraticAndLinearDegenerateCases) {
  // p(u) = (u - 0.25)^2 on [0, 1] (c3 = 0): minimum 0 at u = 0.25.
  EXPECT_NEAR(CubicHermiteMinimum(0.0, 0.0625, -0.5, 1.0, 0.5625, 1.5), 0.0, 1e-16);
  // A straight line: the smaller end.
  EXPECT_EQ(CubicHermiteMinimum(0.0, 1.0, 2.0, 1.0, 3.0, 2.0), 1.0);
}

// The error for a smooth non-polynomial function is O(h^4) of the step.
TEST(CubicHermiteMinimumTest, FourthOrderForACosine) {
  double previous = 0.0;
  for (const double h : {0.8, 0.4, 0.2}) {
    // cos has its minimum -1 at pi; the step [pi - h/3, pi + 2h/3] contains it.
    const double a = M_PI - h / 3.0, b = M_PI + 2.0 * h / 3.0;
    const double err = std::abs(
        CubicHermiteMinimum(a, std::cos(a), -std::sin(a), b, std::cos(b), -std::sin(b)) + 1.0);
    if (previous > 0.0) {
      EXPECT_GT(previous / err, 12.0);  // 16 for h^4
    }
    previous = err;
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::math
