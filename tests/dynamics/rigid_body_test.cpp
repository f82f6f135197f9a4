// The reduced rigid-body equations (dynamics/rigid_body.h): the angular velocity from the
// momentum, Euler's equation in momentum form, the quaternion kinematics, the inertial
// momentum and the kinetic energy, by hand and against independent computations.

#include "deploysim/dynamics/rigid_body.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

namespace deploysim::dynamics {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Mat3;
using math::Quat;
using math::Vec3;
using math::Vec4;

InertiaSample Sample(const Mat3& J, const Vec3& h_rel = Vec3::Zero()) {
  InertiaSample s;
  s.J_B = J;
  s.J_inv_B = J.inverse();
  s.h_rel_B = h_rel;
  s.Jdot_B.setZero();
  return s;
}

/// A full symmetric positive definite inertia (principal moments 2, 3, 4 turned).
Mat3 FullInertia() {
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, -1.0).normalized()).toRotationMatrix();
  return R * Vec3(2.0, 3.0, 4.0).asDiagonal() * R.transpose();
}

// w = J^-1 (H - h_rel): by hand for J = diag(2, 4, 5), and J w + h_rel = H for a full J.
TEST(RigidBodyTest, AngularVelocityIsJInverseOfTheMomentumLessTheRelativeOne) {
  const InertiaSample d = Sample(Vec3(2.0, 4.0, 5.0).asDiagonal(), Vec3(0.5, -1.0, 2.0));
  EXPECT_LT((AngularVelocity(d, Vec3(1.5, 3.0, 7.0)) - Vec3(0.5, 1.0, 1.0)).norm(), 1e-16);
  const InertiaSample f = Sample(FullInertia(), Vec3(0.1, 0.2, 0.3));
  const Vec3 H(1.0, -2.0, 0.5);
  const Vec3 w = AngularVelocity(f, H);
  EXPECT_LT((f.J_B * w + f.h_rel_B - H).norm(), 2e-15);  // measured 6.3e-16
}

// dH/dt = H x w: by hand; it keeps |H| (H . dH/dt = 0) and, with constant J and no
// relative momentum, the energy (w . dH/dt = 0); a spin about a principal axis is steady.
TEST(RigidBodyTest, MomentumRateIsHCrossW) {
  EXPECT_EQ(MomentumRate(Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0)), Vec3(0.0, 0.0, 1.0));
  EXPECT_EQ(MomentumRate(Vec3(0.0, 2.0, 0.0), Vec3(0.0, 0.0, 3.0)), Vec3(6.0, 0.0, 0.0));
  const InertiaSample f = Sample(FullInertia());
  const Vec3 H(1.0, -2.0, 0.5);
  const Vec3 w = AngularVelocity(f, H);
  const Vec3 Hdot = MomentumRate(H, w);
  EXPECT_NEAR(H.dot(Hdot), 0.0, 1e-16);  // measured 0
  EXPECT_NEAR(w.dot(Hdot), 0.0, 1e-16);  // measured 4.3e-18
  const InertiaSample d = Sample(Vec3(2.0, 4.0, 5.0).asDiagonal());
  EXPECT_EQ(MomentumRate(Vec3(0.0, 0.0, 3.0), AngularVelocity(d, Vec3(0.0, 0.0, 3.0))),
            Vec3::Zero());
}

// dq/dt = 1/2 q (0, w) as Eigen's (x, y, z, w): by hand at the identity, and against a
// central difference of the exact motion q(t) = q0 exp(w t / 2) for constant w (measured
// 6.4e-12 with step 1e-5, the difference's own error; bound 2e-11).
TEST(RigidBodyTest, QuaternionRateIsHalfQTimesW) {
  const Vec4 at_identity = QuaternionRate(Quat::Identity(), Vec3(0.2, -0.4, 0.6));
  EXPECT_EQ(at_identity, Vec4(0.1, -0.2, 0.3, 0.0));
  const Quat q0 = Quat(Eigen::AngleAxisd(1.3, Vec3(0.3, -0.5, 0.8).normalized()));
  const Vec3 w(0.7, -1.1, 0.4);
  auto q = [&](double t) {
    return Quat(q0 * Quat(Eigen::AngleAxisd(w.norm() * t, w.normalized())));
  };
  const double h = 1e-5;
  const Vec4 fd = (q(h).coeffs() - q(-h).coeffs()) / (2.0 * h);
  const Vec4 rate = QuaternionRate(q0, w);
  std::printf("quaternion rate vs central difference: %.2e\n", (rate - fd).norm());
  EXPECT_LT((rate - fd).norm(), 2e-11);
  // It is tangent to the unit sphere: q . dq/dt = 0.
  EXPECT_NEAR(q0.coeffs().dot(rate), 0.0, 1e-16);  // measured 2.8e-17
}

// h_N = R_NB H_B, the same as the rotation matrix's product.
TEST(RigidBodyTest, InertialMomentumIsTheRotatedBodyMomentum) {
  const Quat q = Quat(Eigen::AngleAxisd(0.9, Vec3(1.0, 1.0, 0.0).normalized()));
  const Vec3 H(0.3, -1.2, 2.0);
  EXPECT_LT((InertialMomentum(q, H) - q.toRotationMatrix() * H).norm(), 1e-15);
  // A quarter turn about z takes x to y.
  const Quat z90(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
  EXPECT_LT((InertialMomentum(z90, Vec3(2.0, 0.0, 0.0)) - Vec3(0.0, 2.0, 0.0)).norm(),
            1e-15);  // measured 4.4e-16
}

// T = 1/2 w . J w with w from the momentum less the relative one: by hand, and for a full
// inertia equal to 1/2 (H - h_rel) . J^-1 (H - h_rel).
TEST(RigidBodyTest, KineticEnergyIsHalfWJW) {
  // J = diag(2, 4, 5), w = (0.5, 1, 1): T = (0.5 + 4 + 5) / 2.
  const InertiaSample d = Sample(Vec3(2.0, 4.0, 5.0).asDiagonal(), Vec3(0.5, -1.0, 2.0));
  EXPECT_NEAR(KineticEnergy(d, Vec3(1.5, 3.0, 7.0)), 4.75, 1e-15);
  const InertiaSample f = Sample(FullInertia());
  const Vec3 H(1.0, -2.0, 0.5);
  const Vec3 Jinv_H = f.J_B.ldlt().solve(H);
  EXPECT_NEAR(KineticEnergy(f, H), 0.5 * H.dot(Jinv_H), 1e-15);  // measured 4.4e-16
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::dynamics
