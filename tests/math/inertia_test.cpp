#include "deploysim/math/inertia.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "deploysim/math/so3.h"

namespace deploysim::math {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

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

// An entry above 1e30 kg m^2 in magnitude would overflow M^2 and the energies: rejected.
TEST(InertiaTest, RejectsHugeEntries) {
  ExpectRejected(Vec3(1e31, 1e31, 1e31).asDiagonal(), "rule: |entry| <= 1e+30 kg m^2");
  EXPECT_EQ(InertiaTensor::Check(Vec3(1e30, 1e30, 1e30).asDiagonal()), "");
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

/// AccuratePrincipalDecomposition: residual |J V - V diag(l)| and |V^T V - I| evaluated in
/// double-double, relative to |J| (measured 1.0e-31; the double decomposition gives ~1e-15).
constexpr double kAccurateDecompositionTol = 4e-31;

TEST(InertiaTest, AccurateDecompositionResidualIsAtDoubleDoubleRounding) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst_res = 0.0, worst_orth = 0.0, worst_double = 0.0;
  for (int i = 0; i < 300; ++i) {
    const Mat3 R = ExpSO3(Vec3(u(rng), u(rng), u(rng)) * 3.0);
    // Moments from well separated to nearly equal (gaps down to 1e-8 of the scale).
    const double gap = std::pow(10.0, -8.0 * (0.5 + 0.5 * u(rng)));
    const Vec3 m(1.0, 1.0 + gap, 1.7 + 0.2 * u(rng));
    Mat3 J = R * m.asDiagonal() * R.transpose();
    J = 0.5 * (J + J.transpose()).eval();
    const PrincipalAxesDD p = AccuratePrincipalDecomposition(J);
    const double scale = J.norm();
    for (int a = 0; a < 3; ++a) {
      for (int k = 0; k < 3; ++k) {
        DoubleDouble JV = 0.0, VtV = 0.0;
        for (int j = 0; j < 3; ++j) {
          JV += p.V[j][a] * J(k, j);
          VtV += p.V[j][a] * p.V[j][k];
        }
        worst_res = std::max(worst_res,
                             std::abs(static_cast<double>(JV - p.V[k][a] * p.moments[a])) / scale);
        worst_orth =
            std::max(worst_orth, std::abs(static_cast<double>(VtV - (a == k ? 1.0 : 0.0))));
      }
    }
    EXPECT_LE(p.moments[0], p.moments[1]);
    EXPECT_LE(p.moments[1], p.moments[2]);
    const PrincipalAxes r = p.Rounded();
    EXPECT_GT(r.axes.determinant(), 0.0);
    const PrincipalAxes d = PrincipalDecomposition(J);
    worst_double =
        std::max(worst_double, (J * d.axes - d.axes * d.moments.asDiagonal()).norm() / scale);
  }
  EXPECT_LE(worst_res, kAccurateDecompositionTol);
  EXPECT_LE(worst_orth, kAccurateDecompositionTol);
  EXPECT_GT(worst_double, 1e3 * kAccurateDecompositionTol);  // what the refinement removes
  std::printf(
      "[ measured ] accurate decomposition: residual %.2e, orthogonality %.2e "
      "(double decomposition residual %.2e)\n",
      worst_res, worst_orth, worst_double);
}

TEST(InertiaTest, AccurateDecompositionOfDiagonalInputIsExact) {
  const Mat3 J = Vec3(2.5, 1.0, 1.75).asDiagonal();
  const PrincipalAxesDD p = AccuratePrincipalDecomposition(J);
  EXPECT_EQ(p.moments[0], DoubleDouble(1.0));
  EXPECT_EQ(p.moments[1], DoubleDouble(1.75));
  EXPECT_EQ(p.moments[2], DoubleDouble(2.5));
  const PrincipalAxes r = p.Rounded();
  EXPECT_EQ(r.axes, PrincipalDecomposition(J).axes);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_EQ(p.V[i][j].lo(), 0.0);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::math
