#include "deploysim/model/mass_matrix.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "deploysim/model/point_geometry.h"

namespace deploysim::model {

namespace {

using geometry::PointInertia;
using geometry::UnitAxisRotation;

using math::Mat3;
using math::Vec3;

}  // namespace

PanelTree::PanelTree(const HingedBody& body) : n_(static_cast<int>(body.panels.size())) {
  const auto n = static_cast<std::size_t>(n_);
  parent_.resize(n);
  depth_.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const int p = body.panels[k].parent;
    if (p < -1 || p >= n_ || p == static_cast<int>(k)) {
      throw std::invalid_argument("PanelTree: panel " + std::to_string(k) + " has parent " +
                                  std::to_string(p) +
                                  " (rule: -1 for the hub or another panel's index)");
    }
    parent_[k] = p;
  }
  // Depths by walking up (at most n steps each: a longer walk is a cycle).
  for (std::size_t k = 0; k < n; ++k) {
    int d = 1;
    int p = parent_[k];
    while (p >= 0) {
      if (++d > n_) {
        throw std::invalid_argument("PanelTree: the parents of panel " + std::to_string(k) +
                                    " form a cycle (rule: panels form a tree)");
      }
      p = parent_[static_cast<std::size_t>(p)];
    }
    depth_[k] = d;
  }
  // Parents before children: stable order by depth.
  order_.reserve(n);
  int max_depth = 0;
  for (int d : depth_) max_depth = std::max(max_depth, d);
  for (int d = 1; d <= max_depth; ++d) {
    for (int k = 0; k < n_; ++k) {
      if (depth_[static_cast<std::size_t>(k)] == d) order_.push_back(k);
    }
  }
  moves_.assign(n * n, 0);
  for (int i = 0; i < n_; ++i) {
    for (int k = i; k >= 0; k = parent_[static_cast<std::size_t>(k)]) {
      moves_[static_cast<std::size_t>(k) * n + static_cast<std::size_t>(i)] = 1;
    }
  }
}

void ComputePose(const HingedBody& body,
                 const PanelTree& tree,
                 const Eigen::VectorXd& theta,
                 TreePose& pose) {
  const int n = tree.size();
  if (theta.size() != n) {
    throw std::invalid_argument("ComputePose: " + std::to_string(theta.size()) +
                                " hinge angles for " + std::to_string(n) +
                                " panels (rule: one angle per panel)");
  }
  pose.panels.resize(static_cast<std::size_t>(n));
  TreePose::Part& hub = pose.hub;
  hub.R_BP = Mat3::Identity();
  hub.origin_B = Vec3::Zero();
  hub.com_B = body.hub.com_B;
  hub.I_B = body.hub.body.inertia_cm;
  hub.mass = body.hub.body.mass;
  double M = hub.mass;
  Vec3 m_x = hub.mass * hub.com_B;
  for (int k : tree.order()) {
    const Panel& panel = body.panels[static_cast<std::size_t>(k)];
    const int p = tree.parent(k);
    const TreePose::Part& parent = p < 0 ? hub : pose.panels[static_cast<std::size_t>(p)];
    TreePose::Part& part = pose.panels[static_cast<std::size_t>(k)];
    if (p < 0) {
      // A child of the hub (the usual case): the parent's frame is B itself.
      part.axis_B = panel.hinge_axis_B;
      part.origin_B = panel.hinge_point_B;
      part.R_BP = UnitAxisRotation(part.axis_B, theta[k]);
    } else {
      part.axis_B = parent.R_BP * panel.hinge_axis_B;
      part.origin_B = parent.origin_B + parent.R_BP * panel.hinge_point_B;
      part.R_BP = UnitAxisRotation(part.axis_B, theta[k]) * parent.R_BP;
    }
    part.com_B = part.origin_B + part.R_BP * panel.com_offset_B;
    const Mat3 RI = part.R_BP * panel.body.inertia_cm;
    part.I_B.noalias() = RI * part.R_BP.transpose();
    part.mass = panel.body.mass;
    M += part.mass;
    m_x += part.mass * part.com_B;
  }
  pose.mass = M;
  pose.com_B = m_x / M;
}

void ComputeMassMatrix(const HingedBody& /*body*/,
                       const PanelTree& tree,
                       const TreePose& pose,
                       const std::vector<int>& columns,
                       Eigen::MatrixXd& M,
                       bool hub_held) {
  const int m = static_cast<int>(columns.size());
  M.resize(3 + m, 3 + m);
  M.setZero();
  const Vec3& c = pose.com_B;
  Mat3 J = pose.hub.I_B + pose.hub.mass * PointInertia(pose.hub.com_B - c);
  // g_k = sum_{i in D(k)} m_i j_ik, for the CoM-shift term of M_tt (on the stack for the
  // usual few columns: this runs at every Runge-Kutta stage).
  constexpr int kStackColumns = 16;
  std::array<Vec3, kStackColumns> g_stack;
  std::vector<Vec3> g_heap;
  Vec3* g = g_stack.data();
  if (m > kStackColumns) {
    g_heap.resize(static_cast<std::size_t>(m));
    g = g_heap.data();
  }
  for (int a = 0; a < m; ++a) g[a].setZero();
  for (int i = 0; i < tree.size(); ++i) {
    const TreePose::Part& body_i = pose.panels[static_cast<std::size_t>(i)];
    const double mi = body_i.mass;
    const Vec3 rho = body_i.com_B - c;
    J += body_i.I_B + mi * PointInertia(rho);
    for (int a = 0; a < m; ++a) {
      const int k = columns[static_cast<std::size_t>(a)];
      if (!tree.Moves(k, i)) continue;
      const TreePose::Part& hk = pose.panels[static_cast<std::size_t>(k)];
      const Vec3 jk = hk.axis_B.cross(body_i.com_B - hk.origin_B);
      const Vec3 Ia = body_i.I_B * hk.axis_B;
      M.block<3, 1>(0, 3 + a) += mi * rho.cross(jk) + Ia;
      g[a] += mi * jk;
      for (int b = a; b < m; ++b) {
        const int l = columns[static_cast<std::size_t>(b)];
        if (!tree.Moves(l, i)) continue;
        const TreePose::Part& hl = pose.panels[static_cast<std::size_t>(l)];
        const Vec3 jl = hl.axis_B.cross(body_i.com_B - hl.origin_B);
        M(3 + a, 3 + b) += mi * jk.dot(jl) + hl.axis_B.dot(Ia);
      }
    }
  }
  for (int a = 0; a < m; ++a) {
    for (int b = a; b < m; ++b) {
      if (!hub_held) M(3 + a, 3 + b) -= g[a].dot(g[b]) / pose.mass;
      M(3 + b, 3 + a) = M(3 + a, 3 + b);
    }
    M.block<1, 3>(3 + a, 0) = M.block<3, 1>(0, 3 + a).transpose();
  }
  M.block<3, 3>(0, 0) = 0.5 * (J + J.transpose());
}

void ComputeVelocity(const HingedBody& /*body*/,
                     const PanelTree& tree,
                     const TreePose& pose,
                     const Vec3& w_NB_B,
                     const Eigen::VectorXd& theta_dot,
                     TreeVelocity& vel) {
  const int n = tree.size();
  if (theta_dot.size() != n) {
    throw std::invalid_argument("ComputeVelocity: " + std::to_string(theta_dot.size()) +
                                " hinge rates for " + std::to_string(n) +
                                " panels (rule: one rate per panel)");
  }
  vel.panels.resize(static_cast<std::size_t>(n));
  vel.hub.Omega_B = w_NB_B;
  vel.hub.U_B = Vec3::Zero();
  vel.hub.u_B = w_NB_B.cross(pose.hub.com_B);
  Vec3 m_u = pose.hub.mass * vel.hub.u_B;
  for (int k : tree.order()) {
    const int p = tree.parent(k);
    const TreePose::Part& pp = p < 0 ? pose.hub : pose.panels[static_cast<std::size_t>(p)];
    const TreeVelocity::Part& vp = p < 0 ? vel.hub : vel.panels[static_cast<std::size_t>(p)];
    const TreePose::Part& part = pose.panels[static_cast<std::size_t>(k)];
    TreeVelocity::Part& v = vel.panels[static_cast<std::size_t>(k)];
    v.Omega_B = vp.Omega_B + theta_dot[k] * part.axis_B;
    v.U_B = vp.U_B + vp.Omega_B.cross(part.origin_B - pp.origin_B);
    v.u_B = v.U_B + v.Omega_B.cross(part.com_B - part.origin_B);
    m_u += part.mass * v.u_B;
  }
  vel.V_c = m_u / pose.mass;
}

void ComputeMassMatrixInSpeeds(const HingedBody& body,
                               const PanelTree& tree,
                               const TreePose& pose,
                               const Eigen::MatrixXd& speeds,
                               std::vector<TreeVelocity>& fields,
                               Eigen::MatrixXd& M) {
  const auto c = static_cast<Eigen::Index>(speeds.cols());
  const int n = tree.size();
  // The usual layout, (w, then speeds that move hinges only): the w block is J_B about the
  // CoM and its coupling the speeds' angular momenta about it, with no sweep for w.
  const Eigen::Index first = c >= 3 && speeds.topLeftCorner<3, 3>().isIdentity(0.0) &&
                                     speeds.block(3, 0, n, 3).isZero(0.0) &&
                                     speeds.block(0, 3, 3, c - 3).isZero(0.0)
                                 ? 3
                                 : 0;
  fields.resize(static_cast<std::size_t>(c));
  // Per speed: the parts' velocities relative to the system CoM and I_i Omega_i (the
  // latter kept in U_B, no longer needed once u_B - V_c is formed).
  Eigen::VectorXd rates(n);
  for (Eigen::Index a = first; a < c; ++a) {
    const auto col = speeds.col(a);
    rates = col.tail(n);
    TreeVelocity& f = fields[static_cast<std::size_t>(a)];
    ComputeVelocity(body, tree, pose, col.head<3>(), rates, f);
    f.hub.u_B -= f.V_c;
    f.hub.U_B = pose.hub.I_B * f.hub.Omega_B;
    for (int i = 0; i < n; ++i) {
      TreeVelocity::Part& v = f.panels[static_cast<std::size_t>(i)];
      v.u_B -= f.V_c;
      v.U_B = pose.panels[static_cast<std::size_t>(i)].I_B * v.Omega_B;
    }
  }
  M.resize(c, c);
  if (first == 3) {
    const Vec3& cm = pose.com_B;
    Mat3 J = pose.hub.I_B + pose.hub.mass * PointInertia(pose.hub.com_B - cm);
    for (const TreePose::Part& p : pose.panels) J += p.I_B + p.mass * PointInertia(p.com_B - cm);
    M.topLeftCorner<3, 3>() = 0.5 * (J + J.transpose());
    for (Eigen::Index a = 3; a < c; ++a) {
      const TreeVelocity& f = fields[static_cast<std::size_t>(a)];
      Vec3 L = pose.hub.mass * (pose.hub.com_B - cm).cross(f.hub.u_B) + f.hub.U_B;
      for (int i = 0; i < n; ++i) {
        const TreePose::Part& p = pose.panels[static_cast<std::size_t>(i)];
        const TreeVelocity::Part& v = f.panels[static_cast<std::size_t>(i)];
        L += p.mass * (p.com_B - cm).cross(v.u_B) + v.U_B;
      }
      M.block<3, 1>(0, a) = L;
      M.block<1, 3>(a, 0) = L.transpose();
    }
  }
  for (Eigen::Index a = first; a < c; ++a) {
    for (Eigen::Index b = a; b < c; ++b) {
      const TreeVelocity& fa = fields[static_cast<std::size_t>(a)];
      const TreeVelocity& fb = fields[static_cast<std::size_t>(b)];
      double sum = pose.hub.mass * fa.hub.u_B.dot(fb.hub.u_B) + fa.hub.Omega_B.dot(fb.hub.U_B);
      for (int i = 0; i < n; ++i) {
        const TreeVelocity::Part& va = fa.panels[static_cast<std::size_t>(i)];
        const TreeVelocity::Part& vb = fb.panels[static_cast<std::size_t>(i)];
        sum += pose.panels[static_cast<std::size_t>(i)].mass * va.u_B.dot(vb.u_B) +
               va.Omega_B.dot(vb.U_B);
      }
      M(a, b) = sum;
      M(b, a) = sum;
    }
  }
}

double KineticEnergy(const TreePose& pose, const TreeVelocity& vel) {
  auto part_energy = [&](const TreePose::Part& p, const TreeVelocity::Part& v) {
    const Vec3 V = v.u_B - vel.V_c;
    return p.mass * V.squaredNorm() + v.Omega_B.dot(p.I_B * v.Omega_B);
  };
  double two_T = part_energy(pose.hub, vel.hub);
  for (std::size_t i = 0; i < pose.panels.size(); ++i) {
    two_T += part_energy(pose.panels[i], vel.panels[i]);
  }
  return 0.5 * two_T;
}

void KineticEnergyGradient(const PanelTree& tree,
                           const TreePose& pose,
                           const TreeVelocity& vel,
                           const std::vector<int>& wrt,
                           Eigen::VectorXd& grad) {
  const int m = static_cast<int>(wrt.size());
  grad.resize(m);
  grad.setZero();
  for (int i = 0; i < tree.size(); ++i) {
    const TreePose::Part& pi = pose.panels[static_cast<std::size_t>(i)];
    const TreeVelocity::Part& vi = vel.panels[static_cast<std::size_t>(i)];
    const Vec3 mV = pi.mass * (vi.u_B - vel.V_c);
    const Vec3 L = pi.I_B * vi.Omega_B;
    for (int a = 0; a < m; ++a) {
      const int k = wrt[static_cast<std::size_t>(a)];
      if (!tree.Moves(k, i)) continue;
      const TreePose::Part& pk = pose.panels[static_cast<std::size_t>(k)];
      const TreeVelocity::Part& vk = vel.panels[static_cast<std::size_t>(k)];
      const Vec3& ak = pk.axis_B;
      const Vec3 d = pi.com_B - pk.origin_B;
      const Vec3 r = vi.u_B - vk.U_B - vk.Omega_B.cross(d);
      const Vec3 du = vk.Omega_B.cross(ak.cross(d)) + ak.cross(r);
      grad[a] += mV.dot(du) + L.dot(vk.Omega_B.cross(ak));
    }
  }
}

}  // namespace deploysim::model
