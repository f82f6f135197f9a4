#include "deploysim/math/so3.h"

#include <gtest/gtest.h>

#include <random>

#include "deploysim/math/quaternion.h"

namespace deploysim::math {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

constexpr double kTight = 1e-14;

Vec3 RandomVec(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return scale * Vec3(u(rng), u(rng), u(rng));
}

TEST(So3Test, HatVeeRoundTripAndCross) {
  const Vec3 a(0.3, -1.2, 2.5);
  const Vec3 b(-0.7, 0.1, 0.4);
  EXPECT_LT((Hat(a) * b - a.cross(b)).norm(), kTight);
  EXPECT_LT((Vee(Hat(a)) - a).norm(), kTight);
}

TEST(So3Test, ExpIsRotationAndLogInverts) {
  std::mt19937_64 rng(42);
  for (double scale : {1e-10, 1e-6, 1e-4, 1e-2, 1.0, 1.8}) {
    for (int i = 0; i < 200; ++i) {
      const Vec3 phi = RandomVec(rng, scale);
      const Mat3 R = ExpSO3(phi);
      EXPECT_LT((R.transpose() * R - Mat3::Identity()).norm(), 4e-15);
      EXPECT_NEAR(R.determinant(), 1.0, 4e-15);
      EXPECT_LT((LogSO3(R) - phi).norm(), 1e-14 * std::max(1.0, phi.norm()));
      EXPECT_LT((ExpQuat(phi).toRotationMatrix() - R).norm(), 4e-15);
      EXPECT_LT((LogQuat(ExpQuat(phi)) - phi).norm(), 1e-14 * std::max(1.0, phi.norm()));
    }
  }
}

TEST(So3Test, LogNearPi) {
  const Vec3 axis = Vec3(1.0, -2.0, 0.5).normalized();
  for (double eps : {1e-3, 1e-7, 1e-10, 0.0}) {
    const Vec3 phi = (M_PI - eps) * axis;
    const Vec3 back = LogSO3(ExpSO3(phi));
    // At pi, +axis and -axis are the same rotation.
    const double err = std::min((back - phi).norm(), (back + phi).norm());
    EXPECT_LT(err, 1e-7) << "eps=" << eps;
    EXPECT_LT((ExpSO3(back) - ExpSO3(phi)).norm(), 1e-14);
  }
}

TEST(So3Test, ExpMatchesRodriguesSmallAngleSeries) {
  // Continuity across the series/closed-form switch.
  const Vec3 axis = Vec3(0.2, 0.3, -0.9).normalized();
  const Mat3 below = ExpSO3((1e-4 * (1 - 1e-12)) * axis);
  const Mat3 above = ExpSO3((1e-4 * (1 + 1e-12)) * axis);
  EXPECT_LT((below - above).norm(), 1e-15);
}

TEST(So3Test, DexpInvInvertsRightJacobianNumerically) {
  // For R(s) = Exp(u + s v'): R^T dR/ds at s=0 equals hat(J_r(u) v'), so
  // J_r^{-1}(u) applied to the body rate must give back v'.
  std::mt19937_64 rng(7);
  for (int i = 0; i < 50; ++i) {
    const Vec3 u = RandomVec(rng, 2.0);
    const Vec3 du = RandomVec(rng, 1.0);
    const double s = 1e-6;
    const Mat3 Rp = ExpSO3(u + s * du);
    const Mat3 Rm = ExpSO3(u - s * du);
    const Vec3 w = Vee(ExpSO3(u).transpose() * (Rp - Rm) / (2 * s));
    EXPECT_LT((DexpInv(u, w) - du).norm(), 1.5e-9);  // measured 3.8e-10 (finite difference)
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::math
