// The flip rule (analysis/flip_rule.h): the roles of principal axes, the run's spin axis,
// where it lies in a changing inertia, the flip function and its rate, and which sign
// changes of it count as flips.

#include "deploysim/analysis/flip_rule.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace deploysim::analysis {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Mat3;
using math::Vec3;

/// A fixed proper rotation, far from the identity and from any permutation.
Mat3 Turn() { return Eigen::AngleAxisd(1.1, Vec3(1.0, -2.0, 0.5).normalized()).toRotationMatrix(); }

/// R diag(m) R^T.
Mat3 Rotated(const Mat3& R, const Vec3& m) { return R * m.asDiagonal() * R.transpose(); }

/// Rotation by `angle` about body z.
Mat3 Rz(double angle) { return Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix(); }

TEST(FlipRuleTest, RolesAreMinorIntermediateMajorUnlessTwoMomentsAreEqual) {
  const Vec3 distinct(1.0, 2.0, 3.0);
  EXPECT_EQ(RoleOf(distinct, 0), AxisRole::kMinor);
  EXPECT_EQ(RoleOf(distinct, 1), AxisRole::kIntermediate);
  EXPECT_EQ(RoleOf(distinct, 2), AxisRole::kMajor);
  // Two upper moments equal (an oblate body): the minor axis keeps its role, the other two
  // are not distinguished.
  const Vec3 oblate(1.0, 2.0, 2.0);
  EXPECT_EQ(RoleOf(oblate, 0), AxisRole::kMinor);
  EXPECT_EQ(RoleOf(oblate, 1), AxisRole::kDegenerate);
  EXPECT_EQ(RoleOf(oblate, 2), AxisRole::kDegenerate);
  const Vec3 prolate(1.0, 1.0, 3.0);
  EXPECT_EQ(RoleOf(prolate, 0), AxisRole::kDegenerate);
  EXPECT_EQ(RoleOf(prolate, 1), AxisRole::kDegenerate);
  EXPECT_EQ(RoleOf(prolate, 2), AxisRole::kMajor);
  // The tie is relative to the largest moment, kDegenerateMoments = 1e-9: moments 3 and
  // 3 + 2e-9 (gap 0.67e-9 of the largest) are equal, 3 and 3 + 6e-9 (2e-9) are not.
  EXPECT_EQ(RoleOf(Vec3(1.0, 3.0, 3.0 + 2e-9), 1), AxisRole::kDegenerate);
  EXPECT_EQ(RoleOf(Vec3(1.0, 3.0, 3.0 + 2e-9), 2), AxisRole::kDegenerate);
  EXPECT_EQ(RoleOf(Vec3(1.0, 3.0, 3.0 + 6e-9), 1), AxisRole::kIntermediate);
  EXPECT_EQ(RoleOf(Vec3(1.0, 3.0, 3.0 + 6e-9), 2), AxisRole::kMajor);
  // The same scale for the lower pair: 1e-9 of 3 is 3e-9.
  EXPECT_EQ(RoleOf(Vec3(1.0, 1.0 + 2.5e-9, 3.0), 0), AxisRole::kDegenerate);
  EXPECT_EQ(RoleOf(Vec3(1.0, 1.0 + 3.5e-9, 3.0), 0), AxisRole::kMinor);
  EXPECT_EQ(ToString(AxisRole::kMinor), "minor");
  EXPECT_EQ(ToString(AxisRole::kIntermediate), "intermediate");
  EXPECT_EQ(ToString(AxisRole::kMajor), "major");
  EXPECT_EQ(ToString(AxisRole::kDegenerate), "degenerate");
}

// A diagonal inertia keeps its body axes (PrincipalDecomposition is exact there): the spin
// axis is the body axis of the largest momentum component, with that component's sign.
TEST(FlipRuleTest, InitialSpinAxisIsTheBodyAxisNearestTheMomentumSignedAlongIt) {
  const Mat3 J = Vec3(3.0, 1.0, 2.0).asDiagonal();
  EXPECT_EQ(InitialSpinAxis(J, Vec3(0.1, -5.0, 0.2)), Vec3(0.0, -1.0, 0.0));
  EXPECT_EQ(InitialSpinAxis(J, Vec3(0.1, 5.0, 0.2)), Vec3(0.0, 1.0, 0.0));
  EXPECT_EQ(InitialSpinAxis(J, Vec3(-2.0, 1.0, 1.9)), Vec3(-1.0, 0.0, 0.0));
  EXPECT_EQ(InitialSpinAxis(J, Vec3(0.3, 0.2, 0.31)), Vec3(0.0, 0.0, 1.0));
}

// A rotated inertia: the spin axis is the rotated principal axis, to rounding (measured
// |error| 1.4e-16 and 2e-16).
TEST(FlipRuleTest, InitialSpinAxisOfARotatedInertiaIsTheRotatedPrincipalAxis) {
  const Mat3 R = Turn();
  const Mat3 J = Rotated(R, Vec3(1.0, 2.0, 3.0));
  // H mostly along -(axis 1), a little along the others.
  const Vec3 H = R * Vec3(0.3, -4.0, 0.2);
  const Vec3 s = InitialSpinAxis(J, H);
  EXPECT_LT((s - (-R.col(1))).norm(), 1e-15) << s.transpose();
  EXPECT_NEAR(s.norm(), 1.0, 4e-16);
  const Vec3 s2 = InitialSpinAxis(J, R * Vec3(1.0, 0.9, -0.95));
  EXPECT_LT((s2 - R.col(0)).norm(), 1e-15) << s2.transpose();
}

// Where a spin axis s lies in J: the principal axis nearest s, signed along s, and its
// role, whether s is nearly on that axis or 40 degrees off it.
TEST(FlipRuleTest, LocateSpinAxisFindsTheNearestAxisAndItsRole) {
  const Mat3 R = Turn();
  const Mat3 J = Rotated(R, Vec3(1.0, 2.0, 3.0));
  const math::PrincipalAxes p = math::PrincipalDecomposition(J);
  struct Case {
    Vec3 s_principal;  // spin axis in the principal frame
    int axis;
    double sign;
    AxisRole role;
  };
  const double c40 = std::cos(40.0 * M_PI / 180.0), s40 = std::sin(40.0 * M_PI / 180.0);
  for (const Case& c : {Case{Vec3(0.01, 1.0, -0.02), 1, 1.0, AxisRole::kIntermediate},
                        Case{Vec3(0.0, -c40, s40), 1, -1.0, AxisRole::kIntermediate},
                        Case{Vec3(-c40, 0.0, s40), 0, -1.0, AxisRole::kMinor},
                        Case{Vec3(s40, 0.0, c40), 2, 1.0, AxisRole::kMajor}}) {
    const Vec3 s = R * c.s_principal;
    const SpinAxisRole r = LocateSpinAxis(J, s);
    EXPECT_EQ(r.role, c.role) << c.s_principal.transpose();
    EXPECT_LT((r.axis_B - c.sign * R.col(c.axis)).norm(), 1e-15) << c.s_principal.transpose();
    EXPECT_GT(r.axis_B.dot(s), 0.0);
    // The overload that takes the decomposition gives the same bits.
    const SpinAxisRole q = LocateSpinAxis(p, s);
    EXPECT_EQ(q.axis_B, r.axis_B);
    EXPECT_EQ(q.role, r.role);
  }
  // Two moments equal: the axes between them have no role of their own.
  const Mat3 oblate = Rotated(R, Vec3(1.0, 2.0, 2.0));
  EXPECT_EQ(LocateSpinAxis(oblate, R.col(2)).role, AxisRole::kDegenerate);
  EXPECT_EQ(LocateSpinAxis(oblate, R.col(1)).role, AxisRole::kDegenerate);
  EXPECT_EQ(LocateSpinAxis(oblate, -R.col(0)).role, AxisRole::kMinor);
  EXPECT_LT((LocateSpinAxis(oblate, -R.col(0)).axis_B + R.col(0)).norm(), 1e-15);
}

// g = H_B . a with a the principal axis nearest s, signed along s: by hand for a
// diagonal inertia; for a rotated one the component of H along the rotated axis.
TEST(FlipRuleTest, FlipFunctionIsTheMomentumAlongTheSignedSpinAxis) {
  const Mat3 J = Vec3(3.0, 1.0, 2.0).asDiagonal();
  const Vec3 H(0.5, -2.0, 7.0);
  EXPECT_EQ(FlipFunction(J, Vec3(0.1, 1.0, 0.0), H), -2.0);
  EXPECT_EQ(FlipFunction(J, Vec3(0.1, -1.0, 0.0), H), 2.0);
  EXPECT_EQ(FlipFunction(J, Vec3(-0.8, 0.0, 0.6), H), -0.5);
  EXPECT_EQ(FlipFunction(J, Vec3(0.0, 0.3, 0.9), H), 7.0);
  const Mat3 R = Turn();
  const Mat3 Jr = Rotated(R, Vec3(1.0, 2.0, 3.0));
  const Vec3 Hp(0.5, -2.0, 7.0);  // principal components
  EXPECT_NEAR(FlipFunction(Jr, R * Vec3(0.0, -1.0, 0.1), R * Hp), 2.0, 5e-15);  // measured 0
  EXPECT_NEAR(FlipFunction(Jr, R * Vec3(0.1, 0.0, 1.0), R * Hp), 7.0, 5e-15);   // measured 1.8e-15
}

// An inertia turning rigidly at rate w about z under a fixed momentum: a(t) = Rz(w t) a0,
// so g(t) = H . Rz(w t) a0 and dg/dt = H . (w z x a) exactly (the first-order axis
// change of the header's formula is w z x a here, with no truncation).
TEST(FlipRuleTest, FlipFunctionRateOfATurningInertiaIsTheClosedForm) {
  const Vec3 m(1.0, 2.0, 3.0);
  const double w = 0.5;
  const Vec3 H(0.4, 1.5, -0.7);
  const Vec3 Hdot(-0.2, 0.3, 0.1);
  double worst = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    for (double t : {0.0, 0.4, 1.3, 2.9}) {
      // Tilt the principal frame off z so that the turn moves every axis.
      const Mat3 R0 = Eigen::AngleAxisd(0.6, Vec3::UnitX()).toRotationMatrix();
      const Mat3 R = Rz(w * t) * R0;
      const Mat3 J = Rotated(R, m);
      // J' = W J - J W with W = hat(w z).
      Mat3 W;
      W << 0.0, -w, 0.0, w, 0.0, 0.0, 0.0, 0.0, 0.0;
      const Mat3 Jdot = W * J - J * W;
      const Vec3 s = R.col(axis);
      const Vec3 a = R.col(axis);
      const double expected = Hdot.dot(a) + H.dot(w * Vec3::UnitZ().cross(a));
      const double rate = FlipFunctionRate(J, Jdot, s, H, Hdot);
      worst = std::max(worst, std::abs(rate - expected));
      EXPECT_NEAR(rate, expected, 2e-15) << "axis " << axis << ", t = " << t;
      // And a flipped spin axis flips the sign of g and of its rate.
      EXPECT_NEAR(FlipFunctionRate(J, Jdot, -s, H, Hdot), -expected, 2e-15);
    }
  }
  std::printf("flip function rate of a turning inertia vs closed form: %.3g\n", worst);
}

// The flip function's rate against a central difference along a body whose inertia
// turns and stretches while its momentum turns (moved from tests/run/grazing_events_test.cpp).
TEST(FlipRuleTest, FlipFunctionRateIsTheDerivative) {
  auto J = [](double t) {
    const Mat3 R = Eigen::AngleAxisd(0.3 * t, Vec3(1, 2, 3).normalized()).matrix();
    const Vec3 m(2.0 + 0.1 * t, 3.0 - 0.2 * t * t, 4.0 + 0.05 * t);
    return Mat3(R * m.asDiagonal() * R.transpose());
  };
  auto H = [](double t) { return Vec3(std::cos(0.7 * t), 0.2 * std::sin(t), 1.0 + 0.1 * t); };
  const Vec3 s = InitialSpinAxis(J(0.0), H(0.0));
  double worst = 0.0;
  for (double t = 0.1; t < 2.0; t += 0.3) {
    const double h = 1e-5;
    const Mat3 Jdot = (J(t + h) - J(t - h)) / (2 * h);
    const Vec3 Hdot = (H(t + h) - H(t - h)) / (2 * h);
    const double fd =
        (FlipFunction(J(t + h), s, H(t + h)) - FlipFunction(J(t - h), s, H(t - h))) / (2 * h);
    const double rate = FlipFunctionRate(J(t), Jdot, s, H(t), Hdot);
    worst = std::max(worst, std::abs(rate - fd));
    EXPECT_NEAR(rate, fd, 5e-10) << "t = " << t;  // measured 7.6e-11
  }
  std::printf("flip function rate vs central difference: %.3g\n", worst);
}

// With the spin axis in a pair of equal moments the axis change towards the other axis of
// the pair is undefined; that term is left out and the rest is the formula's:
// J = diag(1, 2, 2), a = y (or whichever axis of the y-z pair the decomposition gives),
// dg/dt = Hdot . a + (H . x)(x . J' a) / (2 - 1).
TEST(FlipRuleTest, FlipFunctionRateLeavesOutTheTermOfEqualMoments) {
  const Mat3 J = Vec3(1.0, 2.0, 2.0).asDiagonal();
  Mat3 Jdot;
  Jdot << 0.1, 0.5, 0.0, 0.5, 0.2, 1.0, 0.0, 1.0, -0.3;
  const Vec3 s = Vec3::UnitY();
  const Vec3 H(0.7, 1.5, -0.4);
  const Vec3 Hdot(0.1, -0.2, 0.3);
  const Vec3 a = LocateSpinAxis(J, s).axis_B;
  ASSERT_GT(a.dot(s), 0.9);
  const double expected = Hdot.dot(a) + H.x() * Vec3::UnitX().dot(Jdot * a) / (2.0 - 1.0);
  const double rate = FlipFunctionRate(J, Jdot, s, H, Hdot);
  ASSERT_TRUE(std::isfinite(rate));
  EXPECT_NEAR(rate, expected, 1e-16);
  EXPECT_NEAR(rate, -0.2 + 0.7 * 0.5, 1e-16);  // a = y: by hand (measured 2.8e-17)
}

// A sign change counts when the spin axis is intermediate and |g| <= 1e-6 |H| there.
TEST(FlipRuleTest, AFlipIsASignChangeAboutTheIntermediateAxis) {
  const Mat3 J = Vec3(1.0, 2.0, 3.0).asDiagonal();
  const Vec3 y = Vec3::UnitY();
  EXPECT_TRUE(IsFlip(J, y, Vec3(3.0, 0.0, 4.0)));
  // |H| = 5 (to 1e-12): the residual bound is 5e-6.
  EXPECT_TRUE(IsFlip(J, y, Vec3(3.0, 4.9e-6, 4.0)));
  EXPECT_TRUE(IsFlip(J, -y, Vec3(3.0, -4.9e-6, 4.0)));
  EXPECT_FALSE(IsFlip(J, y, Vec3(3.0, 5.1e-6, 4.0)));
  EXPECT_FALSE(IsFlip(J, y, Vec3(3.0, -5.1e-6, 4.0)));
  // The same zero of g about the minor or the major axis is a wobble, not a flip.
  EXPECT_FALSE(IsFlip(J, Vec3::UnitX(), Vec3(0.0, 3.0, 4.0)));
  EXPECT_FALSE(IsFlip(J, Vec3::UnitZ(), Vec3(3.0, 4.0, 0.0)));
  // Two equal moments: no intermediate axis, no flip.
  EXPECT_FALSE(IsFlip(Vec3(1.0, 2.0, 2.0).asDiagonal(), y, Vec3(3.0, 0.0, 4.0)));
  // A rotated inertia: the intermediate axis is R's second column.
  const Mat3 R = Turn();
  const Mat3 Jr = Rotated(R, Vec3(1.0, 2.0, 3.0));
  EXPECT_TRUE(IsFlip(Jr, R.col(1), R * Vec3(3.0, 0.0, 4.0)));
  EXPECT_FALSE(IsFlip(Jr, R.col(1), R * Vec3(3.0, 1e-4, 4.0)));
}

// FlipEvent: the momentum along the intermediate axis of a constant inertia; refused
// when two moments are equal.
TEST(FlipRuleTest, FlipEventIsTheMomentumAlongTheIntermediateAxis) {
  const Mat3 R = Turn();
  const math::InertiaTensor J = math::InertiaTensor::FromMatrix(Rotated(R, Vec3(1.0, 2.0, 3.0)));
  const integrators::EventFunction e = FlipEvent(J);
  EXPECT_EQ(e.name, "flip");
  integrators::State y;
  y.H_B = R * Vec3(0.3, 2.0, -1.1);
  const double g = e.g(y);
  EXPECT_NEAR(std::abs(g), 2.0, 1e-15);  // measured 0
  y.H_B = R * Vec3(0.3, -2.0, -1.1);
  EXPECT_NEAR(e.g(y), -g, 1e-15);
  y.H_B = R * Vec3(0.3, 0.0, -1.1);
  EXPECT_NEAR(e.g(y), 0.0, 1e-15);  // measured 1.3e-16
  try {
    FlipEvent(math::InertiaTensor::FromPrincipalMoments(Vec3(2.0, 1.0, 2.0)));
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& ex) {
    EXPECT_NE(std::string(ex.what()).find("no intermediate axis"), std::string::npos) << ex.what();
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::analysis
