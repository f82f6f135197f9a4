#pragma once

/// Internal to the steppers: the rigid body's state as a vector y = (H_B, q.coeffs())
/// in R^7 (q.coeffs() = (x, y, z, w)) and its right-hand side.

#include <Eigen/Core>

#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/integrators/problem.h"

namespace deploysim::integrators {

using Vec7 = Eigen::Matrix<double, 7, 1>;

/// y' = (H_B x w, 1/2 q (0, w)), w = J_B(t)^-1 (H_B - h_rel_B(t)). One evaluation.
inline Vec7 RigidBodyDerivative(const Problem& problem, double t, const Vec7& y) {
  const dynamics::InertiaSample s = problem.Sample(t);
  const math::Vec3 H = y.head<3>();
  const math::Vec3 w = dynamics::AngularVelocity(s, H);
  const math::Quat q(y[6], y[3], y[4], y[5]);
  Vec7 dy;
  dy.head<3>() = dynamics::MomentumRate(H, w);
  dy.tail<4>() = dynamics::QuaternionRate(q, w);
  return dy;
}

inline Vec7 ToVec(const State& s) {
  Vec7 v;
  v.head<3>() = s.H_B;
  v.tail<4>() = s.q_NB.coeffs();
  return v;
}

/// The state of a vector at t, the quaternion renormalized.
inline State FromVec(double t, const Vec7& v) {
  State s;
  s.t = t;
  s.H_B = v.head<3>();
  s.q_NB = math::Quat(v[6], v[3], v[4], v[5]).normalized();
  return s;
}

}  // namespace deploysim::integrators
