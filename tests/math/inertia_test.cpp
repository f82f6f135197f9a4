#include "deploysim/math/inertia.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "deploysim/math/so3.h"

namespace deploysim::math {
namespace {

void ExpectRejected(const Mat3& J, const std::string& rule) {
  try {
    InertiaTensor::FromMatrix(J, "test.yaml: inertia");
    FAIL() << "accepted an invalid tensor; expected rule " << rule;
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(rule), std::string::npos) << msg;
    EXPECT_NE(msg.find("test.yaml: inertia"), std::string::npos) << msg;
  }
}

TEST(InertiaTest, AcceptsWingNutAndSortsPrincipalMoments) {
  const InertiaTensor J = InertiaTensor::FromPrincipalMoments(Vec3(3.036e-6, 2.741e-6, 0.699e-6));
  const PrincipalAxes p = J.Principal();
  EXPECT_EQ(p.moments[0], 0.699e-6);
  EXPECT_EQ(p.moments[1], 2.741e-6);
  EXPECT_EQ(p.moments[2], 3.036e-6);
  EXPECT_EQ(p.axes.col(0), Vec3::UnitZ());
  EXPECT_EQ(p.axes.col(1), Vec3::UnitY());
  EXPECT_NEAR(p.axes.determinant(), 1.0, 1e-15);
  EXPECT_LT((J.matrix() * J.inverse() - Mat3::Identity()).norm(), 1e-14);
}

TEST(InertiaTest, FullTensorDecompositionIsRightHanded) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    const Mat3 R = ExpSO3(Vec3(u(rng), u(rng), u(rng)) * 3.0);
    const Vec3 m(1.0 + 0.2 * u(rng), 1.2 + 0.2 * u(rng), 1.5 + 0.2 * u(rng));
    const Mat3 J = R * m.asDiagonal() * R.transpose();
    const PrincipalAxes p = InertiaTensor::FromMatrix(0.5 * (J + J.transpose())).Principal();
    EXPECT_NEAR(p.axes.determinant(), 1.0, 1e-12);
    EXPECT_LT((p.axes * p.moments.asDiagonal() * p.axes.transpose() - J).norm(), 1e-12);
    EXPECT_LE(p.moments[0], p.moments[1]);
    EXPECT_LE(p.moments[1], p.moments[2]);
  }
}

TEST(InertiaTest, RejectsNonFinite) {
  Mat3 J = Vec3(1, 2, 2.5).asDiagonal();
  J(1, 1) = std::numeric_limits<double>::quiet_NaN();
  ExpectRejected(J, "rule: finite");
  J(1, 1) = std::numeric_limits<double>::infinity();
  ExpectRejected(J, "rule: finite");
}

TEST(InertiaTest, RejectsNonSymmetric) {
  Mat3 J = Vec3(1, 2, 2.5).asDiagonal();
  J(0, 1) = 0.1;
  ExpectRejected(J, "rule: symmetric");
}

TEST(InertiaTest, RejectsNegativeOrZeroMoments) {
  ExpectRejected(Vec3(-1, 2, 2.5).asDiagonal(), "rule: positive definite");
  ExpectRejected(Vec3(0, 2, 2).asDiagonal(), "rule: positive definite");
  ExpectRejected(Mat3::Zero(), "rule: positive definite");
}

TEST(InertiaTest, RejectsTriangleInequality) {
  ExpectRejected(Vec3(1, 1, 2.5).asDiagonal(), "rule: triangle inequality");
  // A thin plate (I_a + I_b = I_c) is valid.
  EXPECT_NO_THROW(InertiaTensor::FromPrincipalMoments(Vec3(1, 2, 3)));
}

}  // namespace
}  // namespace deploysim::math
