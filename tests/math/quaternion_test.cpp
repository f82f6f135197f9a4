// Quaternion helpers (math/quaternion.h): the scalar-first conversions, the one rule for
// an attitude handed to the library (ValidateUnitQuaternion and its message), ExpQuat
// against the half-angle closed form in long double, LogQuat as its inverse, and
// AngleBetween.

#include "deploysim/math/quaternion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

namespace deploysim::math {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

/// Random directions and angles in [scale / 2, scale].
struct RotationVectors {
  explicit RotationVectors(unsigned seed) : rng(seed) {}
  Vec3 Next(double scale) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const Vec3 d = Vec3(u(rng), u(rng), u(rng)).normalized();
    return scale * (0.5 + 0.5 * std::abs(u(rng))) * d;
  }
  std::mt19937_64 rng;
};

/// The message of ValidateUnitQuaternion(q, what), or "" if it accepts q.
std::string Rejection(const Quat& q, const std::string& what) {
  try {
    ValidateUnitQuaternion(q, what);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// Moved from tests/math/so3_test.cpp.
TEST(QuaternionTest, WxyzIsScalarFirst) {
  const Quat q(0.5, -0.5, 0.5, 0.5);  // Eigen's constructor is (w, x, y, z)
  const Vec4 v = ToWxyz(q);
  EXPECT_EQ(v[0], 0.5);
  EXPECT_EQ(v[1], -0.5);
  EXPECT_TRUE(FromWxyz(v).coeffs().isApprox(q.coeffs()));
}

// The conversions move numbers only: exact both ways, and FromWxyz does not normalize.
TEST(QuaternionTest, WxyzConversionsAreExactAndDoNotNormalize) {
  const Vec4 wxyz(2.0, -0.1, 0.3, 7.0);
  const Quat q = FromWxyz(wxyz);
  EXPECT_EQ(q.w(), 2.0);
  EXPECT_EQ(q.x(), -0.1);
  EXPECT_EQ(q.y(), 0.3);
  EXPECT_EQ(q.z(), 7.0);
  EXPECT_EQ(ToWxyz(q), wxyz);
  // Eigen's storage is (x, y, z, w): the conversion is not a copy of the coefficients.
  EXPECT_EQ(q.coeffs(), Vec4(-0.1, 0.3, 7.0, 2.0));
}

// Accepted within 1e-12 of norm 1 and returned normalized (the same direction, norm 1 to
// an ulp); rejected beyond, or not finite, with a message that names the quantity, gives
// the components and the norm so that they read back, and states the rule.
TEST(QuaternionTest, ValidateUnitQuaternionAcceptsNormOneWithinTheToleranceOnly) {
  const Quat unit = ExpQuat(Vec3(0.3, -0.2, 0.9));
  for (double f : {1.0, 1.0 + 0.9e-12, 1.0 - 0.9e-12}) {
    const Quat q(f * unit.w(), f * unit.x(), f * unit.y(), f * unit.z());
    ASSERT_EQ(Rejection(q, "q"), "") << f;
    const Quat n = ValidateUnitQuaternion(q, "q");
    EXPECT_NEAR(n.norm(), 1.0, 2.3e-16) << f;
    EXPECT_LT((n.coeffs() - unit.coeffs()).norm(), 4e-16) << f;
  }
  for (double f : {1.0 + 2e-12, 1.0 - 2e-12, 2.0, 0.0}) {
    const Quat q(f * unit.w(), f * unit.x(), f * unit.y(), f * unit.z());
    EXPECT_NE(Rejection(q, "q"), "") << f;
  }
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_NE(Rejection(Quat(std::nan(""), 0.0, 0.0, 0.0), "q"), "");
  EXPECT_NE(Rejection(Quat(1.0, inf, 0.0, 0.0), "q"), "");
  EXPECT_NE(Rejection(Quat(1.0, 0.0, 0.0, std::nan("")), "q"), "");

  // The message: "<what> = (w, x, y, z) has norm <n> (rule: ...)"; w first.
  const Quat bad(0.1, 0.2, 0.3, 0.4);
  const std::string m = Rejection(bad, "profile.yaml: attitude_wxyz");
  const std::string head = "profile.yaml: attitude_wxyz = (";
  ASSERT_EQ(m.rfind(head, 0), 0u) << m;
  const char* p = m.c_str() + head.size();
  char* end = nullptr;
  for (double expected : {0.1, 0.2, 0.3, 0.4}) {
    EXPECT_EQ(std::strtod(p, &end), expected) << m;
    ASSERT_NE(end, p) << m;
    p = end;
    while (*p == ',' || *p == ' ' || *p == ')') ++p;
  }
  ASSERT_EQ(std::string(p).rfind("has norm ", 0), 0u) << m;
  EXPECT_EQ(std::strtod(p + 9, &end), bad.norm()) << m;
  EXPECT_NE(m.find("rule: a finite unit quaternion"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

// ExpQuat(phi) = (cos(a/2), sin(a/2) phi/a), a = |phi|, against the same in long double,
// on both sides of the series for a^2 < 1e-8 (a = 1e-4) and up to a = 3: measured
// 2.4e-16 per component (5.6e-17 below a = 1) and norm 1 within 2.2e-16; bounds 5e-16.
TEST(QuaternionTest, ExpQuatIsTheHalfAngleClosedForm) {
  RotationVectors rv(7);
  double worst = 0.0, worst_norm = 0.0;
  for (double scale : {1e-12, 1e-6, 0.99e-4, 1.01e-4, 2e-4, 1e-2, 1.0, 3.0}) {
    for (int i = 0; i < 1000; ++i) {
      const Vec3 phi = rv.Next(scale);
      const long double x = phi.x(), y = phi.y(), z = phi.z();
      const long double a = std::sqrt(x * x + y * y + z * z);
      const long double c = std::cos(a / 2), s = std::sin(a / 2) / a;
      const Quat q = ExpQuat(phi);
      const double err =
          static_cast<double>(std::max({std::abs(q.w() - c), std::abs(q.x() - s * x),
                                        std::abs(q.y() - s * y), std::abs(q.z() - s * z)}));
      worst = std::max(worst, err);
      worst_norm = std::max(worst_norm, std::abs(q.norm() - 1.0));
      EXPECT_LT(err, 5e-16) << phi.transpose();
    }
  }
  std::printf("ExpQuat against long double: %.2e, |norm - 1| %.2e\n", worst, worst_norm);
  EXPECT_LT(worst_norm, 5e-16);
  EXPECT_EQ(ExpQuat(Vec3::Zero()).coeffs(), Quat::Identity().coeffs());
}

// LogQuat inverts ExpQuat for angles below pi (relative error measured 4.0e-16, bound
// 1.5e-15, including the series for |v| < 1e-8), gives the same for q and -q, and maps an
// angle beyond pi to the shorter rotation about the opposite axis.
TEST(QuaternionTest, LogQuatInvertsExpQuatAndIgnoresTheSign) {
  RotationVectors rv(11);
  double worst = 0.0;
  for (double scale : {1e-12, 1e-8, 1e-6, 1e-2, 1.0, 3.0}) {
    for (int i = 0; i < 1000; ++i) {
      const Vec3 phi = rv.Next(scale);
      const Quat q = ExpQuat(phi);
      const Vec3 back = LogQuat(q);
      const double rel = (back - phi).norm() / phi.norm();
      worst = std::max(worst, rel);
      EXPECT_LT(rel, 1.5e-15) << phi.transpose();
      const Quat minus(-q.w(), -q.x(), -q.y(), -q.z());
      EXPECT_EQ(LogQuat(minus), back);
    }
  }
  std::printf("LogQuat(ExpQuat(phi)) relative error %.2e\n", worst);
  const Vec3 axis = Vec3(1.0, -2.0, 0.5).normalized();
  EXPECT_LT((LogQuat(ExpQuat(4.0 * axis)) + (2.0 * M_PI - 4.0) * axis).norm(), 2e-15);
  for (double eps : {1e-3, 1e-7, 1e-10}) {
    const Vec3 phi = (M_PI - eps) * axis;
    EXPECT_LT((LogQuat(ExpQuat(phi)) - phi).norm(), 2e-15) << eps;
  }
  // At pi, +axis and -axis are the same rotation; either may come back, of length pi.
  EXPECT_NEAR(LogQuat(ExpQuat(M_PI * axis)).norm(), M_PI, 2e-15);
}

// Moved from tests/math/so3_test.cpp.
TEST(QuaternionTest, AngleBetweenIgnoresSign) {
  const Quat a = ExpQuat(Vec3(0.1, 0.2, 0.3));
  Quat b = ExpQuat(Vec3(0.1, 0.2, 0.3) + Vec3(0.0, 0.0, 0.25));
  const double d = AngleBetween(a, b);
  b.coeffs() = -b.coeffs();
  EXPECT_NEAR(AngleBetween(a, b), d, 1e-15);
  EXPECT_GT(d, 0.2);
}

// AngleBetween(q0, q0 ExpQuat(phi)) is |phi| for any q0, from 1e-12 rad to 3 rad:
// measured within 8.9e-16 rad (the rounding of the product), bound 3e-15; symmetric.
TEST(QuaternionTest, AngleBetweenIsTheAngleOfTheRelativeRotation) {
  RotationVectors rv(13);
  double worst = 0.0;
  for (double scale : {1e-12, 1e-6, 1e-2, 1.0, 3.0}) {
    for (int i = 0; i < 1000; ++i) {
      const Vec3 phi = rv.Next(scale);
      const Quat q0 = ExpQuat(rv.Next(3.0));
      const Quat q1 = q0 * ExpQuat(phi);
      const double err = std::abs(AngleBetween(q0, q1) - phi.norm());
      worst = std::max(worst, err);
      EXPECT_LT(err, 3e-15) << phi.transpose();
      EXPECT_NEAR(AngleBetween(q1, q0), AngleBetween(q0, q1), 1e-15);
    }
  }
  std::printf("AngleBetween error %.2e rad\n", worst);
  EXPECT_EQ(AngleBetween(Quat::Identity(), Quat::Identity()), 0.0);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::math
