#include "deploysim/model/mass_properties.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "deploysim/math/inertia.h"
#include "deploysim/math/number_format.h"
#include "deploysim/model/point_geometry.h"

namespace deploysim::model {

namespace {

using geometry::PointInertia;
using geometry::UnitAxisRotation;

using math::Mat3;
using math::Vec3;

/// A validated hinge axis has |a|^2 = 1 to rounding; ComputeMassProperties rejects axes
/// further from unit length than this (they were not normalized by ValidatedHingedBody).
constexpr double kUnitAxisTolerance = 1e-12;

/// dS(d)/dt = 2 (d . d') I - d' d^T - d d'^T.
Mat3 PointInertiaRate(const Vec3& d, const Vec3& d_dot) {
  const double xx = 2.0 * d.x() * d_dot.x();
  const double yy = 2.0 * d.y() * d_dot.y();
  const double zz = 2.0 * d.z() * d_dot.z();
  const double xy = d.x() * d_dot.y() + d.y() * d_dot.x();
  const double xz = d.x() * d_dot.z() + d.z() * d_dot.x();
  const double yz = d.y() * d_dot.z() + d.z() * d_dot.y();
  Mat3 S;
  S << yy + zz, -xy, -xz,  //
      -xy, xx + zz, -yz,   //
      -xz, -yz, xx + yy;
  return S;
}

std::string Fmt(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

std::string Fmt(const Vec3& v) {
  std::ostringstream os;
  os.precision(17);
  os << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return os.str();
}

std::string PanelLabel(const std::string& where, std::size_t k, const Panel& p) {
  std::string label = where + ": panels[" + std::to_string(k) + "]";
  if (!p.name.empty()) label += " (" + p.name + ")";
  return label;
}

void CheckMass(double mass, const std::string& what) {
  if (!(std::isfinite(mass) && mass > 0.0)) {
    throw std::invalid_argument(what + ".mass = " + Fmt(mass) +
                                ": must be finite and > 0 (rule: mass > 0)");
  }
  if (!(mass <= kMaxPartMass)) {
    throw std::invalid_argument(what + ".mass = " + Fmt(mass) + ": too large (rule: mass <= " +
                                math::FormatNumber(kMaxPartMass) + " kg)");
  }
}

void CheckFinite(const Vec3& v, const std::string& what) {
  if (!v.allFinite()) {
    throw std::invalid_argument(what + " = " + Fmt(v) +
                                ": every component must be finite (rule: finite)");
  }
}

/// A position [m]: finite, every component within kMaxCoordinate.
void CheckPosition(const Vec3& v, const std::string& what) {
  CheckFinite(v, what);
  if (!(v.cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
    throw std::invalid_argument(what + " = " + Fmt(v) + ": too far from the origin (rule: |" +
                                "component| <= " + math::FormatNumber(kMaxCoordinate) + " m)");
  }
}

/// (J + J^T) / 2, evaluated into a new matrix (no aliasing).
Mat3 Symmetrized(const Mat3& J) {
  const Mat3 S = 0.5 * (J + J.transpose());
  return S;
}

void CheckInertia(const Mat3& J, const std::string& what) {
  const std::string err = math::InertiaTensor::Check(J, what);
  if (!err.empty()) throw std::invalid_argument(err);
}

/// A generated panel (model.h Appendage) of zero inertia: a massless link (mass 0, CoM on
/// its hinge, with a child: the child's mass keeps the mass matrix definite) or a point
/// mass (mass > 0, its CoM off its hinge axis). Returns false for any other panel (checked
/// as usual); throws for a zero-inertia panel that is neither.
bool CheckMasslessOrPoint(const HingedBody& body, std::size_t k, const std::string& label) {
  const Panel& p = body.panels[k];
  if (!p.body.inertia_cm.isZero(0.0) || !std::isfinite(p.body.mass)) return false;
  if (p.body.mass == 0.0) {
    bool has_child = false;
    for (const Panel& q : body.panels) has_child = has_child || q.parent == static_cast<int>(k);
    if (p.com_offset_B.isZero(0.0) && has_child) return true;
    throw std::invalid_argument(label +
                                ".mass = 0: a massless link must have its CoM on its hinge and "
                                "a child (rule: mass > 0, or a link between two hinges)");
  }
  if (p.body.mass > 0.0 && p.body.mass <= kMaxPartMass &&
      p.com_offset_B.cross(p.hinge_axis_B).norm() > 0.0) {
    return true;
  }
  throw std::invalid_argument(label +
                              ".inertia = 0: a point mass must have mass > 0 and its CoM "
                              "off its hinge axis (rule: positive definite inertia, or a point "
                              "mass off the axis)");
}

/// How a panel is named in a list or as a value: its name, or panels[k] if it has none.
std::string PanelName(const HingedBody& body, std::size_t k) {
  const std::string& name = body.panels[k].name;
  return name.empty() ? "panels[" + std::to_string(k) + "]" : name;
}

/// Panel k's parent index: -1 (the hub) or another panel's index.
void CheckParentIndex(const HingedBody& body, std::size_t k, const std::string& where) {
  const Panel& p = body.panels[k];
  const std::string label = PanelLabel(where, k, p);
  const long n = static_cast<long>(body.panels.size());
  if (p.parent < -1 || p.parent >= n) {
    throw std::invalid_argument(label + ".parent = " + std::to_string(p.parent) +
                                ": no such panel (rule: parent is -1 for the hub or the index "
                                "of another panel, 0 to " +
                                std::to_string(n - 1) + ")");
  }
  if (p.parent == static_cast<long>(k)) {
    throw std::invalid_argument(label + ".parent = " + PanelName(body, k) +
                                ": a panel cannot be its own parent (rule: panels form a tree)");
  }
}

/// The parents (indices already checked) form a tree rooted at the hub, no panel more than
/// kMaxPanelDepth deep. A cycle is reported at its panel of lowest index, e.g.
/// "x.yaml: panels[2] (seg_b).parent = seg_c: the panels' parents form a cycle
/// (seg_b -> seg_c -> seg_b) (rule: panels form a tree)".
void CheckTree(const HingedBody& body, const std::string& where) {
  const std::size_t n = body.panels.size();
  const auto parent = [&](std::size_t j) { return body.panels[j].parent; };
  for (std::size_t k = 0; k < n; ++k) {
    // Walk up from k: the hub within n steps, or a cycle.
    std::size_t depth = 1;
    int j = parent(k);
    while (j >= 0 && depth <= n) {
      j = parent(static_cast<std::size_t>(j));
      ++depth;
    }
    if (j >= 0) {
      // After n steps the walk is on the cycle: find its panel of lowest index.
      const auto on_cycle = static_cast<std::size_t>(j);
      std::size_t first = on_cycle;
      for (auto i = static_cast<std::size_t>(parent(on_cycle)); i != on_cycle;
           i = static_cast<std::size_t>(parent(i))) {
        first = std::min(first, i);
      }
      std::string path = PanelName(body, first);
      std::size_t i = first;
      do {
        i = static_cast<std::size_t>(parent(i));
        path += " -> " + PanelName(body, i);
      } while (i != first);
      throw std::invalid_argument(
          PanelLabel(where, first, body.panels[first]) +
          ".parent = " + PanelName(body, static_cast<std::size_t>(parent(first))) +
          ": the panels' parents form a cycle (" + path + ") (rule: panels form a tree)");
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t depth = 1;
    for (int j = parent(k); j >= 0; j = parent(static_cast<std::size_t>(j))) ++depth;
    if (depth > static_cast<std::size_t>(kMaxPanelDepth)) {
      throw std::invalid_argument(
          PanelLabel(where, k, body.panels[k]) +
          ".parent = " + PanelName(body, static_cast<std::size_t>(parent(k))) +
          ": the chain from the hub to " + PanelName(body, k) + " has " + std::to_string(depth) +
          " panels (rule: a chain of panels from the hub has at most " +
          std::to_string(kMaxPanelDepth) + ")");
    }
  }
}

/// Throws if hinge axis a of panel k is not a unit vector (ComputeMassProperties).
void CheckUnitAxis(const Vec3& a, Eigen::Index k) {
  if (!(std::abs(a.squaredNorm() - 1.0) <= kUnitAxisTolerance)) {
    throw std::invalid_argument(
        "ComputeMassProperties: panel " + std::to_string(k) + " hinge axis " + Fmt(a) +
        " is not a unit vector (rule: validate the body with ValidatedHingedBody)");
  }
}

/// Panel k's motion in B (docs/design.md 2.5).
struct PanelMotion {
  Mat3 R;      ///< R_Bk.
  Vec3 y;      ///< [m] its CoM relative to the hub CoM, B.
  Vec3 y_dot;  ///< [m/s] rate of y seen in B.
  Vec3 w_rel;  ///< [rad/s] w_k,rel = sum over k and its ancestors j of theta_j' R_B,parent(j) a_j.
};

/// PanelMotion of panel k, built from its own hinge up through its ancestors without
/// storage (no allocation; the cost is the number of ancestors). While walking up, the
/// fields hold panel k's motion relative to the frame of the panel j reached so far: R its
/// orientation, y (= d below) its CoM from j's hinge point, y_dot its rate and w_rel its
/// angular velocity, all in j's axes. Lifting them into j's parent's frame, with
/// Q = Rot(a_j, theta_j) (j turns on its hinge p_j, fixed in the parent's frame):
///   d <- p_j + Q d,   d' <- Q d' + theta_j' a_j x (Q d),
///   w <- theta_j' a_j + Q w,   R <- Q R,
/// starting from R = I, d = r_k, d' = 0, w = 0 at j = k; for the hub the origin is the hub
/// CoM c_h instead of B's origin (p_j - c_h in place of p_j).
/// A child of the hub takes one step: R = Rot(a_k, theta_k), y = (p_k - c_h) + R r_k,
/// y' = theta_k' a_k x (R r_k), written exactly so (the same bits as before trees).
/// Throws std::invalid_argument for a parent index out of range or a cycle (the body was
/// not validated with ValidatedHingedBody).
PanelMotion MotionInB(const HingedBody& body,
                      const Eigen::VectorXd& theta,
                      const Eigen::VectorXd& theta_dot,
                      Eigen::Index k) {
  const Vec3& c_h = body.hub.com_B;
  const std::size_t n = body.panels.size();
  const auto from_parent_origin = [&](const Panel& p) -> Vec3 {
    return p.parent < 0 ? Vec3(p.hinge_point_B - c_h) : p.hinge_point_B;
  };
  const Panel& panel = body.panels[static_cast<std::size_t>(k)];
  PanelMotion pm;
  pm.R = UnitAxisRotation(panel.hinge_axis_B, theta[k]);
  const Vec3 r = pm.R * panel.com_offset_B;  // Rot(a_k, theta_k) r_k
  pm.y = from_parent_origin(panel) + r;
  pm.y_dot = theta_dot[k] * panel.hinge_axis_B.cross(r);
  pm.w_rel = theta_dot[k] * panel.hinge_axis_B;
  std::size_t steps = 0;
  for (int j = panel.parent; j >= 0;) {
    if (static_cast<std::size_t>(j) >= n || ++steps > n) {
      throw std::invalid_argument("ComputeMassProperties: panel " + std::to_string(k) +
                                  ": its parents do not lead to the hub (rule: panels form a "
                                  "tree; validate the body with ValidatedHingedBody)");
    }
    const Panel& pj = body.panels[static_cast<std::size_t>(j)];
    const Eigen::Index i = j;
    const Mat3 Q = UnitAxisRotation(pj.hinge_axis_B, theta[i]);
    const Vec3 Qd = Q * pm.y;
    const Vec3 y_dot = Q * pm.y_dot + theta_dot[i] * pj.hinge_axis_B.cross(Qd);
    const Vec3 w_rel = theta_dot[i] * pj.hinge_axis_B + Q * pm.w_rel;
    const Mat3 R = Q * pm.R;
    pm.y = from_parent_origin(pj) + Qd;
    pm.y_dot = y_dot;
    pm.w_rel = w_rel;
    pm.R = R;
    j = pj.parent;
  }
  return pm;
}

}  // namespace

MassProperties ComputeMassProperties(const HingedBody& body,
                                     const Eigen::VectorXd& theta,
                                     const Eigen::VectorXd& theta_dot) {
  const Eigen::Index n = static_cast<Eigen::Index>(body.panels.size());
  if (theta.size() != n || theta_dot.size() != n) {
    throw std::invalid_argument("ComputeMassProperties: " + std::to_string(theta.size()) +
                                " hinge angles and " + std::to_string(theta_dot.size()) +
                                " hinge rates for " + std::to_string(n) +
                                " panels (rule: one angle and one rate per panel)");
  }
  if (!theta.allFinite() || !theta_dot.allFinite()) {
    throw std::invalid_argument(
        "ComputeMassProperties: hinge angles and rates must be finite (rule: finite)");
  }

  // Positions y_i are taken relative to the hub CoM c_h (a point fixed in B, near the
  // system CoM, so no digits are lost to a distant origin). Sums about c_h are shifted to
  // the system CoM c = c_h + e at the end, using sum_i m_i (y_i - e) = 0:
  //   sum m S(y - e) = sum m S(y) - M S(e),  sum m (y - e) x y' = sum m y x y' - M e x e'.
  // The hub contributes its own inertia and nothing else (y_hub = 0, y_hub' = 0).
  const Vec3& c_h = body.hub.com_B;
  double M = body.hub.body.mass;
  Vec3 m_y = Vec3::Zero();      // sum m_k y_k            [kg m]
  Vec3 m_y_dot = Vec3::Zero();  // sum m_k y_k'           [kg m/s]
  Mat3 J = body.hub.body.inertia_cm;
  Mat3 Jdot = Mat3::Zero();
  Vec3 h = Vec3::Zero();
  double two_T = 0.0;  // 2 T_rel about c_h: sum m_k |y_k'|^2 + w_k,rel.(I_k w_k,rel) [J]

  for (Eigen::Index k = 0; k < n; ++k) {
    const Panel& panel = body.panels[static_cast<std::size_t>(k)];
    const Vec3& a = panel.hinge_axis_B;
    CheckUnitAxis(a, k);
    const double m = panel.body.mass;
    const double rate = theta_dot[k];
    const PanelMotion pm = MotionInB(body, theta, theta_dot, k);
    const Mat3 I_k = pm.R * panel.body.inertia_cm * pm.R.transpose();  // own inertia, B axes
    const Vec3& y = pm.y;
    const Vec3& y_dot = pm.y_dot;

    // The terms of the panel's own inertia turning at w_k,rel (in B).
    Mat3 Jdot_own;  // d/dt (R_Bk I_k R_Bk^T)
    Vec3 h_own;     // I_k w_k,rel
    double T2_own;  // w_k,rel . I_k w_k,rel
    if (panel.parent < 0) {
      // A child of the hub: w_k,rel = thetadot_k a_k, the terms written with rate and a_k
      // as before panel trees (single-level models give the same bits).
      // [a]x I_k, column by column; I_k [a]x = -([a]x I_k)^T as I_k is symmetric.
      Mat3 A_I;
      for (int j = 0; j < 3; ++j) A_I.col(j) = a.cross(I_k.col(j));
      // d/dt (R I R^T) = theta' ([a]x I_k - I_k [a]x), from R' = theta' [a]x R.
      Jdot_own = rate * (A_I + A_I.transpose());
      const Vec3 I_a = I_k * a;
      h_own = rate * I_a;
      T2_own = rate * rate * a.dot(I_a);
    } else {
      // Deeper in the tree: d/dt (R I R^T) = [w]x I_k - I_k [w]x with w = w_k,rel.
      const Vec3& w = pm.w_rel;
      Mat3 W_I;
      for (int j = 0; j < 3; ++j) W_I.col(j) = w.cross(I_k.col(j));
      Jdot_own = W_I + W_I.transpose();
      h_own = I_k * w;
      T2_own = w.dot(h_own);
    }

    J += I_k;
    J += m * PointInertia(y);
    Jdot += Jdot_own;
    Jdot += m * PointInertiaRate(y, y_dot);
    h += h_own;
    h += m * y.cross(y_dot);
    two_T += m * y_dot.squaredNorm() + T2_own;
    m_y += m * y;
    m_y_dot += m * y_dot;
    M += m;
  }

  const Vec3 e = m_y / M;          // system CoM relative to hub CoM
  const Vec3 e_dot = m_y_dot / M;  // its rate in B
  J -= M * PointInertia(e);
  Jdot -= M * PointInertiaRate(e, e_dot);
  h -= M * e.cross(e_dot);
  // sum_i m_i |y_i' - e'|^2 = sum_i m_i |y_i'|^2 - M |e'|^2 (sum_i m_i y_i' = M e').
  two_T -= M * e_dot.squaredNorm();

  MassProperties out;
  out.mass = M;
  out.com_B = c_h + e;
  out.com_rate_B = e_dot;
  out.J_B = Symmetrized(J);
  out.Jdot_B = Symmetrized(Jdot);
  out.h_rel_B = h;
  out.relative_kinetic_energy = 0.5 * two_T;
  return out;
}

Mat3 BoxInertia(double mass, const Vec3& size) {
  if (!(std::isfinite(mass) && mass > 0.0)) {
    throw std::invalid_argument("BoxInertia: mass = " + Fmt(mass) +
                                ": must be finite and > 0 (rule: mass > 0)");
  }
  if (!size.allFinite() || (size.array() < 0.0).any()) {
    throw std::invalid_argument("BoxInertia: size = " + Fmt(size) +
                                ": edge lengths must be finite and >= 0 (rule: box size >= 0)");
  }
  const Vec3 s2 = size.cwiseProduct(size);
  const Vec3 moments = mass / 12.0 * Vec3(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y());
  Mat3 J = Mat3::Zero();
  J.diagonal() = moments;
  return J;
}

Mat3 AxisAngle(const Vec3& axis, double angle) {
  const double norm = axis.norm();
  if (!(std::isfinite(norm) && norm > 0.0) || !std::isfinite(angle)) {
    throw std::invalid_argument("AxisAngle: axis = " + Fmt(axis) + ", angle = " + Fmt(angle) +
                                ": axis must be finite and non-zero, angle finite "
                                "(rule: non-zero axis)");
  }
  return UnitAxisRotation(axis / norm, angle);
}

HingedBody ValidatedHingedBody(HingedBody body, const std::string& where) {
  CheckMass(body.hub.body.mass, where + ": hub");
  CheckInertia(body.hub.body.inertia_cm, where + ": hub.inertia");
  body.hub.body.inertia_cm = Symmetrized(body.hub.body.inertia_cm);
  CheckPosition(body.hub.com_B, where + ": hub.com");
  for (std::size_t k = 0; k < body.panels.size(); ++k) {
    Panel& p = body.panels[k];
    const std::string label = PanelLabel(where, k, p);
    if (!CheckMasslessOrPoint(body, k, label)) {
      CheckMass(p.body.mass, label);
      CheckInertia(p.body.inertia_cm, label + ".inertia");
    }
    p.body.inertia_cm = Symmetrized(p.body.inertia_cm);
    CheckPosition(p.hinge_point_B, label + ".hinge_point");
    CheckPosition(p.com_offset_B, label + ".com_offset");
    CheckFinite(p.hinge_axis_B, label + ".hinge_axis");
    const double norm = p.hinge_axis_B.stableNorm();
    if (!(norm > 0.0) || !std::isfinite(norm)) {
      throw std::invalid_argument(label + ".hinge_axis = " + Fmt(p.hinge_axis_B) +
                                  ": must have non-zero length (rule: hinge axis non-zero)");
    }
    p.hinge_axis_B /= norm;
    CheckParentIndex(body, k, where);
    if (!p.name.empty()) {
      for (std::size_t j = 0; j < k; ++j) {
        if (body.panels[j].name == p.name) {
          throw std::invalid_argument(label + ".name = " + p.name + ": also the name of panels[" +
                                      std::to_string(j) + "] (rule: unique panel names)");
        }
      }
    }
  }
  CheckTree(body, where);
  return body;
}

}  // namespace deploysim::model
