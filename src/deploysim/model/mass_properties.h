#pragma once

/// J_B(theta) and h_rel_B(theta, theta_dot) of a hub with hinged panels (DESIGN.md 2.5),
/// everything about the SYSTEM centre of mass (which moves as the panels turn).

#include <Eigen/Core>
#include <string>

#include "deploysim/model/model.h"

namespace deploysim::model {

struct MassProperties {
  double mass = 0.0;                           ///< [kg] total.
  math::Vec3 com_B = math::Vec3::Zero();       ///< [m] system CoM in B.
  math::Vec3 com_rate_B = math::Vec3::Zero();  ///< [m/s] its rate seen in B.
  math::Mat3 J_B = math::Mat3::Zero();         ///< [kg m^2] about the system CoM.
  math::Mat3 Jdot_B = math::Mat3::Zero();      ///< [kg m^2/s] dJ_B/dt seen in B.
  /// [kg m^2/s] angular momentum of the motion relative to B, about the system CoM.
  math::Vec3 h_rel_B = math::Vec3::Zero();
  /// [J] T_rel, kinetic energy of the motion relative to B (DESIGN.md 2.7): the
  /// system's kinetic energy about its CoM is 1/2 w.J_B w + w.h_rel_B + T_rel.
  double relative_kinetic_energy = 0.0;
};

/// Mass properties at hinge angles theta [rad] and rates theta_dot [rad/s] (one entry
/// per panel), DESIGN.md 2.5. With R_k = Rot(a_k, theta_k), part CoMs x_i (hub: c_h;
/// panel k: p_k + R_k r_k), system CoM c = sum m_i x_i / M, rho_i = x_i - c and
/// S(d) = |d|^2 I - d d^T:
///   J_B     = sum_i [ R_i I_i R_i^T + m_i S(rho_i) ],
///   Jdot_B  = sum_k thetadot_k ([a_k]x R_k I_k R_k^T - R_k I_k R_k^T [a_k]x)
///             + sum_i m_i dS(rho_i)/dt,
///   h_rel_B = sum_k R_k I_k R_k^T (thetadot_k a_k) + sum_i m_i rho_i x rho_i',
///   com_rate_B = sum_k m_k thetadot_k (a_k x R_k r_k) / M,
///   relative_kinetic_energy T_rel = 1/2 sum_i m_i |rho_i'|^2
///                                 + 1/2 sum_k thetadot_k^2 a_k^T R_k I_k R_k^T a_k,
/// with rho_i' the rate in B of part i's CoM relative to the system CoM, including the
/// CoM-shift term -c' (it cancels in h_rel_B, not in T_rel; the hub's rho' is -c').
/// `body` must have unit hinge axes (as ValidatedHingedBody returns). No heap allocation
/// (it is evaluated at every Runge-Kutta stage). Throws std::invalid_argument if the sizes
/// do not match the panels, an angle or rate is not finite, or a hinge axis is not unit.
MassProperties ComputeMassProperties(const HingedBody& body,
                                     const Eigen::VectorXd& theta,
                                     const Eigen::VectorXd& theta_dot);

/// Inertia of a solid cuboid of the given mass and edge lengths (x, y, z) about its CoM,
/// in its own axes: m/12 diag(y^2+z^2, x^2+z^2, x^2+y^2). A thin plate is a cuboid with
/// a small edge.
math::Mat3 BoxInertia(double mass, const math::Vec3& size);

/// Rotation by angle [rad] about axis (Rodrigues; right-hand rule; the axis is normalized,
/// throws std::invalid_argument if it is zero or not finite).
math::Mat3 AxisAngle(const math::Vec3& axis, double angle);

/// Largest mass of a part [kg] (ValidatedHingedBody): 1e12 kg, far above any spacecraft;
/// with kMaxCoordinate it keeps every inertia below 1e26 kg m^2 (finite and well-scaled:
/// math::InertiaTensor::kMaxEntry is 1e30).
inline constexpr double kMaxPartMass = 1e12;
/// Largest |component| [m] of a position (hub.com, hinge_point, com_offset).
inline constexpr double kMaxCoordinate = 1e6;

/// Checks masses finite and in (0, kMaxPartMass], positions finite with components within
/// kMaxCoordinate, finite vectors, valid inertias (math::InertiaTensor::Check:
/// finite, symmetric, positive definite, triangle inequality), hinge axes of non-zero
/// length and unique non-empty panel names. Returns the body with unit hinge axes and
/// exactly symmetric inertias. Throws std::invalid_argument whose message names `where`
/// (e.g. the file), the part ("hub", "panels[1] (wing_minus_x)"), the key, the value and
/// the rule, e.g. "models/x.yaml: panels[1] (wing_b).mass = -2.5: must be finite and > 0
/// (rule: mass > 0)".
HingedBody ValidatedHingedBody(HingedBody body, const std::string& where);

}  // namespace deploysim::model
