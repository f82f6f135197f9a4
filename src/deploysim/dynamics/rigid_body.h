#pragma once

/// The reduced equations of a torque-free body with time-varying inertia
/// (docs/design.md section 2.1, thesis 2.10-2.21, 2.65):
///   H_B = J_B(t) w_NB_B + h_rel_B(t),   dH_B/dt = H_B x w_NB_B,   dR_NB/dt = R_NB [w_NB_B]x.
/// Invariants: h_N = R_NB H_B is constant; so is |H_B|. The kinetic energy
/// T = 1/2 w^T J w is constant only while J is constant and h_rel = 0.

#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/math/types.h"

namespace deploysim::dynamics {

/// Body-frame angular velocity w_NB_B = J_B^-1 (H_B - h_rel_B) [rad/s].
inline math::Vec3 AngularVelocity(const InertiaSample& s, const math::Vec3& H_B) {
  return s.J_inv_B * (H_B - s.h_rel_B);
}

/// Euler's equation in momentum form: dH_B/dt = H_B x w_NB_B [kg m^2/s^2].
inline math::Vec3 MomentumRate(const math::Vec3& H_B, const math::Vec3& w_NB_B) {
  return H_B.cross(w_NB_B);
}

/// Quaternion kinematics dq_NB/dt = 1/2 q_NB (0, w_NB_B), as 4 Eigen coefficients (x,y,z,w).
math::Vec4 QuaternionRate(const math::Quat& q_NB, const math::Vec3& w_NB_B);

/// Inertial momentum h_N = R_NB H_B [kg m^2/s] (constant for every J(t), h_rel(t)).
inline math::Vec3 InertialMomentum(const math::Quat& q_NB, const math::Vec3& H_B) {
  return q_NB * H_B;
}

/// Kinetic energy of the rotation of B, 1/2 w^T J w [J] (with h_rel = 0 the total
/// rotational kinetic energy; constant only for constant J and h_rel = 0).
double KineticEnergy(const InertiaSample& s, const math::Vec3& H_B);

}  // namespace deploysim::dynamics
