#pragma once

/// The hub + panel tree as a Lagrangian system (docs/design.md 2.7): its pose at hinge angles
/// theta, its mass matrix in the velocities v = (w_NB_B, theta') and the exact gradient
/// dT/dtheta of its kinetic energy at fixed v. Everything about the system centre of
/// mass, in B components, SI units.
///
/// Kinematics (model.h, docs/design.md 2.5). Body 0 is the hub (origin o_0 = B's origin, CoM
/// c_h, angular velocity w); panel k (parent P, hinge point p_k and axis a_k in P's axes)
/// has R_Bk = R_BP Rot(a_k, theta_k), hinge point h_k = o_P + R_BP p_k (its origin o_k),
/// axis in B a^_k = R_BP a_k, CoM x_k = h_k + R_Bk r_k, inertia in B I_k = R_Bk I_k0 R_Bk^T.
/// Velocities, propagated from the root (in a frame in which B's origin is momentarily at
/// rest: only velocities relative to the system CoM enter T):
///   Omega_0 = w,  Omega_k = Omega_P + theta'_k a^_k           (angular velocity)
///   U_0 = 0,      U_k = U_P + Omega_P x (h_k - o_P)           (velocity of origin o_k)
///   u_i = U_i + Omega_i x (x_i - o_i)                         (velocity of CoM i)
///   V_c = sum m_i u_i / M,  V_i = u_i - V_c,  L_i = I_i Omega_i.
/// Kinetic energy T = 1/2 sum_i [m_i |V_i|^2 + Omega_i . L_i] = 1/2 v^T M(theta) v with
///   M = [[J_B, Bm], [Bm^T, M_tt]],   over the hinges k, l of `columns`:
///   J_B      = sum_i [I_i + m_i S(x_i - c)]
///   Bm[:, k] = sum_{i in D(k)} [m_i (x_i - c) x j_ik + I_i a^_k],   j_ik = a^_k x (x_i - h_k)
///   M_kl     = sum_{i in D(k) and D(l)} [m_i j_ik . j_il + a^_k . I_i a^_l] - g_k . g_l / M,
///              g_k = sum_{i in D(k)} m_i j_ik
/// where D(k) is panel k and its descendants (the bodies that turn with hinge k).
/// Gradient at fixed v (rotating the subtree D(k) about (h_k, a^_k)):
///   dT/dtheta_k = sum_{i in D(k)} [ m_i V_i . (Omega_k x (a^_k x d_ik) + a^_k x r_ik)
///                                   + L_i . (Omega_k x a^_k) ],
///   d_ik = x_i - h_k,  r_ik = u_i - U_k - Omega_k x d_ik (velocity of CoM i relative to
///   panel k's frame). Derived by the chain rule from d x_i = a^_k x d_ik,
///   d h_j = a^_k x (h_j - h_k), d a^_j = a^_k x a^_j, d R_Bi = [a^_k]x R_Bi for i, j in D(k)
///   (with the Jacobi identity); checked against Richardson-extrapolated central
///   differences of KineticEnergy in tests/model/mass_matrix_test.cpp.

#include <Eigen/Core>
#include <vector>

#include "deploysim/model/model.h"

namespace deploysim::model {

/// The tree's topology, precomputed once per body: an order with parents before
/// children and the ancestor relation. `body` must be valid (ValidatedHingedBody).
class PanelTree {
 public:
  explicit PanelTree(const HingedBody& body);
  int size() const { return n_; }
  /// Panels with every parent before its children.
  const std::vector<int>& order() const { return order_; }
  int parent(int k) const { return parent_[static_cast<std::size_t>(k)]; }
  /// True when hinge k turns panel i: k is i or one of its ancestors.
  bool Moves(int k, int i) const {
    return moves_[static_cast<std::size_t>(k) * static_cast<std::size_t>(n_) +
                  static_cast<std::size_t>(i)] != 0;
  }
  /// Depth of panel k: 1 for a child of the hub.
  int depth(int k) const { return depth_[static_cast<std::size_t>(k)]; }

 private:
  int n_ = 0;
  std::vector<int> order_;
  std::vector<int> parent_;
  std::vector<int> depth_;
  std::vector<char> moves_;
};

/// Positions and orientations of every part at hinge angles theta (B components).
struct TreePose {
  struct Part {
    math::Mat3 R_BP = math::Mat3::Identity();  ///< orientation of the part in B
    math::Vec3 origin_B = math::Vec3::Zero();  ///< o_k: hinge point (panel), 0 (hub)
    math::Vec3 axis_B = math::Vec3::UnitX();   ///< a^_k (panels)
    math::Vec3 com_B = math::Vec3::Zero();     ///< x_i [m]
    math::Mat3 I_B = math::Mat3::Zero();       ///< [kg m^2] about the part's CoM, B axes
    double mass = 0.0;                         ///< [kg]
  };
  Part hub;
  std::vector<Part> panels;               ///< in the model's panel order
  double mass = 0.0;                      ///< [kg] total
  math::Vec3 com_B = math::Vec3::Zero();  ///< [m] system CoM c
};

/// The pose at theta (one angle per panel, rad). `pose` is resized to the body (no
/// allocation when it already has the size).
void ComputePose(const HingedBody& body,
                 const PanelTree& tree,
                 const Eigen::VectorXd& theta,
                 TreePose& pose);

/// The mass matrix over (w_NB_B, theta'_columns): (3 + m) x (3 + m), m = columns.size(),
/// formulas in the file comment. Symmetric positive definite for a valid body (all
/// masses > 0). `M` is resized (no allocation when it already has the size).
/// hub_held: the hub held still in translation as well (a clamped root): the hinges' block
/// leaves out the CoM-shift term -g_k . g_l / M (used for a clamped beam's frequencies).
void ComputeMassMatrix(const HingedBody& body,
                       const PanelTree& tree,
                       const TreePose& pose,
                       const std::vector<int>& columns,
                       Eigen::MatrixXd& M,
                       bool hub_held = false);

/// Forward declaration for ComputeMassMatrixInSpeeds.
struct TreeVelocity;

/// The mass matrix over generalized speeds that are combinations of (w_NB_B, theta'):
/// speed c moves the system as w = speeds.col(c).head<3>(), theta' = speeds.col(c).tail(n)
/// (n panels), and M_cd = sum over the parts i of m_i V_i^c . V_i^d + Omega_i^c . I_i
/// Omega_i^d, V_i^c the velocity of part i's CoM relative to the system CoM under speed c
/// (ComputeVelocity). It equals T^T M T for M over (w, every hinge) and T = speeds, at
/// O(c n + c^2 n) instead of O(n m^2) for m hinge columns: the form for a few speeds that
/// move many hinges (modal coordinates). `fields` is scratch (one velocity per speed).
void ComputeMassMatrixInSpeeds(const HingedBody& body,
                               const PanelTree& tree,
                               const TreePose& pose,
                               const Eigen::MatrixXd& speeds,
                               std::vector<TreeVelocity>& fields,
                               Eigen::MatrixXd& M);

/// Velocities of every part for body angular velocity w and hinge rates theta_dot (one
/// per panel; zero for hinges at rest), file comment.
struct TreeVelocity {
  struct Part {
    math::Vec3 Omega_B = math::Vec3::Zero();  ///< [rad/s] angular velocity in N, B axes
    math::Vec3 U_B = math::Vec3::Zero();      ///< [m/s] velocity of the part's origin
    math::Vec3 u_B = math::Vec3::Zero();      ///< [m/s] velocity of its CoM
  };
  Part hub;
  std::vector<Part> panels;
  math::Vec3 V_c = math::Vec3::Zero();  ///< [m/s] velocity of the system CoM
};

void ComputeVelocity(const HingedBody& body,
                     const PanelTree& tree,
                     const TreePose& pose,
                     const math::Vec3& w_NB_B,
                     const Eigen::VectorXd& theta_dot,
                     TreeVelocity& vel);

/// Kinetic energy about the system CoM [J], summed part by part (not from the mass
/// matrix): 1/2 sum_i [m_i |u_i - V_c|^2 + Omega_i . I_i Omega_i].
double KineticEnergy(const TreePose& pose, const TreeVelocity& vel);

/// dT/dtheta_k at fixed (w, theta') for each k of `wrt` [N m] (file comment), into
/// grad (resized to wrt.size()).
void KineticEnergyGradient(const PanelTree& tree,
                           const TreePose& pose,
                           const TreeVelocity& vel,
                           const std::vector<int>& wrt,
                           Eigen::VectorXd& grad);

}  // namespace deploysim::model
