#pragma once

/// J_B(theta) and h_rel_B(theta, theta_dot) of a hub with hinged panels (docs/design.md 2.5),
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
  /// [J] T_rel, kinetic energy of the motion relative to B (docs/design.md 2.5): the
  /// system's kinetic energy about its CoM is 1/2 w.J_B w + w.h_rel_B + T_rel.
  double relative_kinetic_energy = 0.0;
};

/// Mass properties at hinge angles theta [rad] and rates theta_dot [rad/s] (one entry
/// per panel), docs/design.md 2.5 (panel trees, model.h). Panel k in B: orientation
/// R_k = R_B,parent(k) Rot(a_k, theta_k), hinge point o_k = o_parent(k) + R_B,parent(k) p_k,
/// CoM x_k = o_k + R_k r_k, relative angular velocity
/// w_k = sum over k and its ancestors j of theta_j' u_j with u_j = R_B,parent(j) a_j
/// (for a child of the hub: R_k = Rot(a_k, theta_k), x_k = p_k + R_k r_k, w_k =
/// theta_k' a_k). With the hub's CoM x_hub = c_h, system CoM c = sum m_i x_i / M,
/// rho_i = x_i - c and S(d) = |d|^2 I - d d^T:
///   J_B     = sum_i [ R_i I_i R_i^T + m_i S(rho_i) ],
///   Jdot_B  = sum_k ([w_k]x R_k I_k R_k^T - R_k I_k R_k^T [w_k]x) + sum_i m_i dS(rho_i)/dt,
///   h_rel_B = sum_k R_k I_k R_k^T w_k + sum_i m_i rho_i x rho_i',
///   com_rate_B = sum_k m_k x_k' / M,  x_k' = sum_j theta_j' u_j x (x_k - o_j),
///   relative_kinetic_energy T_rel = 1/2 sum_i m_i |rho_i'|^2
///                                 + 1/2 sum_k w_k^T R_k I_k R_k^T w_k,
/// with rho_i' the rate in B of part i's CoM relative to the system CoM, including the
/// CoM-shift term -c' (it cancels in h_rel_B, not in T_rel; the hub's rho' is -c').
/// Panels may come in any order relative to their parents. `body` must have unit hinge
/// axes and parents forming a tree (as ValidatedHingedBody returns). No heap allocation
/// (it is evaluated at every Runge-Kutta stage); the cost grows with the sum over panels
/// of their depth in the tree (each panel's chain to the hub is walked). Children of the
/// hub are computed term by term as in the single-level model. Throws
/// std::invalid_argument if the sizes do not match the panels, an angle or rate is not
/// finite, a hinge axis is not unit or the parents do not lead to the hub.
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
/// Most panels on a chain from the hub (a child of the hub is 1 deep): far more segments
/// than any folded array or boom has. It bounds the cost of ComputeMassProperties (each
/// panel's chain is walked) and the distance of a part from B's origin
/// (kMaxPanelDepth * sqrt(3) kMaxCoordinate).
inline constexpr int kMaxPanelDepth = 256;

/// Checks masses finite and in (0, kMaxPartMass] (a generated massless link or point mass
/// excepted: model.h Appendage), positions finite with components within
/// kMaxCoordinate, finite vectors, valid inertias (math::InertiaTensor::Check:
/// finite, symmetric, positive definite, triangle inequality), hinge axes of non-zero
/// length, unique non-empty panel names, and the panel tree: every parent is -1 (the hub)
/// or the index of another panel, the parents have no cycle, and no chain from the hub
/// has more than kMaxPanelDepth panels. Returns the body with unit hinge axes and
/// exactly symmetric inertias. Throws std::invalid_argument whose message names `where`
/// (e.g. the file), the part ("hub", "panels[1] (wing_minus_x)"), the key, the value and
/// the rule, e.g. "models/x.yaml: panels[1] (wing_b).mass = -2.5: must be finite and > 0
/// (rule: mass > 0)", "models/x.yaml: panels[2] (seg_b).parent = seg_c: the panels'
/// parents form a cycle (seg_b -> seg_c -> seg_b) (rule: panels form a tree)" (a parent
/// is shown by name, a cycle from its panel of lowest index).
HingedBody ValidatedHingedBody(HingedBody body, const std::string& where);

}  // namespace deploysim::model
