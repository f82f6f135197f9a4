// Panel trees (docs/design.md 2.5, model.h): a panel's parent is the hub or another panel.
// model::ComputeMassProperties is checked against
//  - bodies built by hand: the two-segment accordion of models/smallsat_two_segment.yaml
//    folded flat (four plates placed with the parallel-axis theorem) and fully open (the
//    single-segment wings of models/smallsat.yaml, each plate split in two), and a
//    single-level body with the outer segment re-hinged on the hub;
//  - an independent brute-force computation for random branched trees with skew hinge
//    axes, listed in random order: every part is a cloud of six point masses with the
//    part's mass, CoM and inertia, placed by explicit rotation compositions from the hub
//    down; J_B is the particles' inertia about their CoM, and Jdot_B, com_rate_B, h_rel_B
//    and T_rel come from central differences of the particles' motion (a test oracle
//    only: the library differentiates analytically).

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <numeric>
#include <random>
#include <sstream>
#include <vector>

#include "deploysim/math/so3.h"
#include "deploysim/model/mass_properties.h"

namespace deploysim::model {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Mat3;
using math::Vec3;

constexpr double kDegree = M_PI / 180.0;
/// The same quantity summed in different ways (a body built by hand, the panels listed in
/// another order), relative to |J_B| (times the rate scale for rates); measured worst
/// 5.0e-16 over the tests below.
constexpr double kRoundoffTolerance = 2e-15;
/// J_B against the particles (whose offsets come from an eigendecomposition): measured
/// worst 9.3e-16 relative.
constexpr double kParticleInertiaTolerance = 4e-15;
/// 4th-order central differences of the particles' motion with step kFiniteDifferenceStep
/// [s], relative to |J_B| max|theta'| (Jdot_B, h_rel_B) or to T_rel. Measured worst over
/// the random trees: Jdot 3.0e-11, h_rel 2.9e-12, T_rel 2.1e-11.
constexpr double kJdotTolerance = 1e-10;
constexpr double kMomentumTolerance = 1e-11;
constexpr double kEnergyTolerance = 1e-10;
constexpr double kFiniteDifferenceStep = 1e-3;
constexpr int kRandomTrees = 200;
constexpr unsigned kSeed = 20261202;

Mat3 S(const Vec3& d) { return d.squaredNorm() * Mat3::Identity() - d * d.transpose(); }

// ---- the two-segment small satellite ------------------------------------------------

/// Numbers duplicated from models/smallsat_two_segment.yaml (keep both in step): the hub of
/// models/smallsat.yaml; each wing an inner and an outer 3 kg, 0.4 x 1.0 m segment, the
/// outer hinged on the inner's far edge, on the inner's outer face.
HingedBody TwoSegmentBody() {
  HingedBody b;
  b.hub.body.mass = 85.0;
  b.hub.body.inertia_cm = BoxInertia(85.0, Vec3(0.6, 1.0, 0.8));
  Panel inner;
  inner.name = "inner_plus_x";
  inner.body.mass = 3.0;
  inner.body.inertia_cm = BoxInertia(3.0, Vec3(0.4, 1.0, 0.02));
  inner.hinge_point_B = Vec3(0.3, 0.0, 0.4);
  inner.hinge_axis_B = Vec3(0.0, 1.0, 0.0);
  inner.com_offset_B = Vec3(0.2, 0.0, 0.01);
  Panel outer = inner;
  outer.name = "outer_plus_x";
  outer.parent = 0;
  outer.hinge_point_B = Vec3(0.4, 0.0, 0.02);
  outer.com_offset_B = Vec3(0.2, 0.0, -0.01);
  // The -x wing is the half-turn-about-y image of the +x wing.
  Panel inner_minus = inner;
  inner_minus.name = "inner_minus_x";
  inner_minus.hinge_point_B = Vec3(-0.3, 0.0, -0.4);
  inner_minus.com_offset_B = Vec3(-0.2, 0.0, -0.01);
  Panel outer_minus = outer;
  outer_minus.name = "outer_minus_x";
  outer_minus.parent = 2;
  outer_minus.hinge_point_B = Vec3(-0.4, 0.0, -0.02);
  outer_minus.com_offset_B = Vec3(-0.2, 0.0, 0.01);
  b.panels = {inner, outer, inner_minus, outer_minus};
  return ValidatedHingedBody(b, "models/smallsat_two_segment.yaml (C++ copy)");
}

/// Hinge angles [rad] of the two-segment body: inner angle, outer angle relative to the
/// inner, the same for both wings (the model's configurations: closed 90, -180; open 0, 0).
Eigen::VectorXd Angles(double inner_deg, double outer_deg) {
  Eigen::VectorXd a(4);
  a << inner_deg, outer_deg, inner_deg, outer_deg;
  return a * kDegree;
}

TEST(PanelTreeTest, AccordionFoldedFlatEqualsTheBodyBuiltByHand) {
  const HingedBody b = TwoSegmentBody();
  const MassProperties mp =
      ComputeMassProperties(b, Angles(90.0, -180.0), Eigen::VectorXd::Zero(4));
  // Stowed, each segment stands upright (0.02 x 1.0 x 0.4 m) beside its hub x-face: the
  // inner ones 1 cm outside the face, the outer ones folded back onto them, 3 cm outside;
  // the +x wing between z = 0 and 0.4, the -x wing between z = -0.4 and 0.
  Mat3 J = BoxInertia(85.0, Vec3(0.6, 1.0, 0.8));
  const Mat3 upright = BoxInertia(3.0, Vec3(0.02, 1.0, 0.4));
  for (const Vec3& c : {Vec3(0.31, 0.0, 0.2), Vec3(0.33, 0.0, 0.2), Vec3(-0.31, 0.0, -0.2),
                        Vec3(-0.33, 0.0, -0.2)}) {
    J += upright + 3.0 * S(c);
  }
  EXPECT_DOUBLE_EQ(mp.mass, 97.0);
  EXPECT_LT(mp.com_B.norm(), 1e-15);
  // Measured 8.9e-17.
  EXPECT_LT((mp.J_B - J).norm(), kRoundoffTolerance * J.norm()) << mp.J_B << "\nvs\n" << J;
}

TEST(PanelTreeTest, AccordionFullyOpenEqualsTheSingleSegmentWings) {
  // Open, each wing is one flat 6 kg 0.8 x 1.0 m plate, as in models/smallsat.yaml.
  HingedBody single;
  single.hub = TwoSegmentBody().hub;
  Panel plus;
  plus.name = "wing_plus_x";
  plus.body.mass = 6.0;
  plus.body.inertia_cm = BoxInertia(6.0, Vec3(0.8, 1.0, 0.02));
  plus.hinge_point_B = Vec3(0.3, 0.0, 0.4);
  plus.hinge_axis_B = Vec3(0.0, 1.0, 0.0);
  plus.com_offset_B = Vec3(0.4, 0.0, 0.01);
  Panel minus = plus;
  minus.name = "wing_minus_x";
  minus.hinge_point_B = Vec3(-0.3, 0.0, -0.4);
  minus.com_offset_B = Vec3(-0.4, 0.0, -0.01);
  single.panels = {plus, minus};
  single = ValidatedHingedBody(single, "models/smallsat.yaml (C++ copy)");
  const Mat3 J_single =
      ComputeMassProperties(single, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()).J_B;
  const Mat3 J_tree =
      ComputeMassProperties(TwoSegmentBody(), Angles(0.0, 0.0), Eigen::VectorXd::Zero(4)).J_B;
  // Measured 2.6e-16.
  EXPECT_LT((J_tree - J_single).norm(), kRoundoffTolerance * J_single.norm()) << J_tree << "\nvs\n"
                                                                              << J_single;
}

TEST(PanelTreeTest, OuterSegmentEqualsAHubPanelAtItsHingePosition) {
  // At inner angle t and relative outer angle f, the outer segment is where a panel hinged
  // on the hub at the outer hinge's B position, turned by t + f (parallel axes), would be.
  // With the inner at rest the rates agree as well; with the inner moving they must not:
  // the outer's hinge then moves (the tree's h_rel has the inner's rate in the outer's
  // terms).
  const HingedBody tree = TwoSegmentBody();
  for (const double t : {90.0, 60.0, 20.0, 0.0}) {
    for (const double f : {-180.0, -120.0, -30.0, 0.0}) {
      HingedBody flat = tree;
      for (std::size_t k : {std::size_t{1}, std::size_t{3}}) {
        const Panel& inner = tree.panels[k - 1];
        Panel& outer = flat.panels[k];
        outer.parent = -1;
        outer.hinge_point_B =
            inner.hinge_point_B + AxisAngle(inner.hinge_axis_B, t * kDegree) * outer.hinge_point_B;
      }
      flat = ValidatedHingedBody(flat, "flat");
      Eigen::VectorXd flat_angles(4);
      flat_angles << t, t + f, t, t + f;
      flat_angles *= kDegree;
      const double outer_rate = 0.3;  // [rad/s] relative to the inner
      Eigen::VectorXd tree_rates(4);
      tree_rates << 0.0, outer_rate, 0.0, outer_rate;
      const MassProperties a = ComputeMassProperties(tree, Angles(t, f), tree_rates);
      const MassProperties c = ComputeMassProperties(flat, flat_angles, tree_rates);
      const double scale = a.J_B.norm();
      EXPECT_LT((a.J_B - c.J_B).norm(), kRoundoffTolerance * scale) << t << " " << f;
      EXPECT_LT((a.com_B - c.com_B).norm(), 1e-15) << t << " " << f;
      EXPECT_LT((a.Jdot_B - c.Jdot_B).norm(), kRoundoffTolerance * scale * outer_rate);
      EXPECT_LT((a.h_rel_B - c.h_rel_B).norm(), kRoundoffTolerance * scale * outer_rate);
      EXPECT_NEAR(a.relative_kinetic_energy, c.relative_kinetic_energy,
                  kRoundoffTolerance * c.relative_kinetic_energy);
      // The inner moving too (both segments at rate -0.2 rad/s relative to their parents):
      // in the flat body the outer turns at the sum of the rates about a fixed hinge; in the
      // tree its hinge moves with the inner, which adds momentum.
      Eigen::VectorXd both(4);
      both << -0.2, -0.2, -0.2, -0.2;
      Eigen::VectorXd flat_both(4);
      flat_both << -0.2, -0.4, -0.2, -0.4;
      const MassProperties a2 = ComputeMassProperties(tree, Angles(t, f), both);
      const MassProperties c2 = ComputeMassProperties(flat, flat_angles, flat_both);
      // Measured 0.16 to 4.5 relative.
      EXPECT_GT((a2.h_rel_B - c2.h_rel_B).norm(), 0.05 * a2.h_rel_B.norm()) << t << " " << f;
    }
  }
}

TEST(PanelTreeTest, AccordionUnfoldingMomentumIsAlongTheSpinAxis) {
  // The half-turn symmetry about y keeps the system CoM at the hub centre and h_rel along
  // y while both wings unfold (inner 90 -> 0, outer -180 -> 0 relative to it): the inner
  // segments turn about -y, the outer ones about +y in B (net -90 -> 0).
  const HingedBody b = TwoSegmentBody();
  Eigen::VectorXd rates(4);
  rates << -9.0, 18.0, -9.0, 18.0;  // [deg/s]
  rates *= kDegree;
  for (double s = 0.0; s <= 1.0; s += 0.125) {
    const MassProperties mp =
        ComputeMassProperties(b, Angles(90.0 * (1.0 - s), -180.0 * (1.0 - s)), rates);
    EXPECT_LT(mp.com_B.norm(), 1e-15) << s;
    EXPECT_LT(mp.com_rate_B.norm(), 1e-15) << s;
    EXPECT_LT(std::abs(mp.h_rel_B.x()) + std::abs(mp.h_rel_B.z()),
              1e-14 * std::abs(mp.h_rel_B.y()) + 1e-16)
        << s;
    EXPECT_LT(std::abs(mp.J_B(0, 1)) + std::abs(mp.J_B(1, 2)), 1e-14 * mp.J_B.norm()) << s;
  }
}

// ---- random branched trees with skew axes against particles --------------------------

Vec3 RandomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  for (;;) {
    const Vec3 v(n(rng), n(rng), n(rng));
    const double norm = v.norm();
    if (norm < 1e-3) continue;
    const Vec3 u = v / norm;
    if (u.cwiseAbs().maxCoeff() <= 0.9) return u;  // not along a B axis
  }
}

Mat3 RandomRotation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  return math::ExpSO3(Vec3(u(rng), u(rng), u(rng)));
}

/// A random tree of 2-7 panels: panel i (in creation order) hangs on the hub or on a
/// random earlier panel (so the tree branches and chains), with a skew hinge axis; the
/// panels are then listed in a random order (parents before or after their children).
HingedBody RandomTree(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  HingedBody b;
  b.hub.body.mass = 50.0 + 50.0 * u(rng);
  const Mat3 Q = RandomRotation(rng);
  b.hub.body.inertia_cm =
      Q * BoxInertia(b.hub.body.mass, Vec3(0.3 + u(rng), 0.3 + u(rng), 0.3 + u(rng))) *
      Q.transpose();
  b.hub.com_B = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * 0.2;
  const int n = 2 + static_cast<int>(u(rng) * 6.0);
  std::vector<int> created_parent(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    // The first two panels hang on the hub and on panel 0: every tree has depth >= 2.
    created_parent[static_cast<std::size_t>(i)] = i == 0   ? -1
                                                  : i == 1 ? 0
                                                           : static_cast<int>(u(rng) * (i + 1)) - 1;
  }
  std::vector<int> order(static_cast<std::size_t>(n));  // order[listed] = created index
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<int> listed(static_cast<std::size_t>(n));  // listed[created] = list index
  for (int k = 0; k < n; ++k)
    listed[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = k;
  for (int k = 0; k < n; ++k) {
    const int created = order[static_cast<std::size_t>(k)];
    const int cp = created_parent[static_cast<std::size_t>(created)];
    Panel p;
    p.name = "panel" + std::to_string(created);
    p.parent = cp < 0 ? -1 : listed[static_cast<std::size_t>(cp)];
    p.body.mass = 1.0 + 9.0 * u(rng);
    const Mat3 R = RandomRotation(rng);
    p.body.inertia_cm =
        R * BoxInertia(p.body.mass, Vec3(0.2 + u(rng), 0.2 + u(rng), 0.01 + 0.05 * u(rng))) *
        R.transpose();
    p.hinge_point_B = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * 1.2;
    p.hinge_axis_B = RandomUnit(rng) * (0.5 + u(rng));  // normalized by validation
    p.com_offset_B = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * 1.5;
    b.panels.push_back(p);
  }
  return ValidatedHingedBody(b, "random tree");
}

Eigen::VectorXd RandomVector(std::mt19937_64& rng, std::size_t n, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Eigen::VectorXd v(static_cast<Eigen::Index>(n));
  for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = u(rng);
  return v;
}

/// Six point masses m/6 at +-d_i e_i about the CoM, in the part's own axes, with the mass,
/// CoM and inertia I of the part: their second moment C = sum mu x x^T must be
/// tr(I)/2 - I (I = tr(C) - C), so along each principal axis e_i of I with moment l_i,
/// 2 (m/6) d_i^2 = tr(I)/2 - l_i (>= 0 by the triangle inequality).
std::vector<Vec3> ParticleOffsets(double m, const Mat3& I) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(I);
  const double half_trace = 0.5 * I.trace();
  std::vector<Vec3> x;
  for (int i = 0; i < 3; ++i) {
    const double d = std::sqrt(std::max(0.0, half_trace - eig.eigenvalues()[i]) / (m / 3.0));
    x.push_back(d * eig.eigenvectors().col(i));
    x.push_back(-d * eig.eigenvectors().col(i));
  }
  return x;
}

struct Particle {
  double mass;
  Vec3 x;  // [m] in B, from B's origin
};

/// Orientation R_Bk and hinge point o_k (in B) of panel k, composed from the hub down:
/// R_Bk = R_B,parent Exp(a_k theta_k), o_k = o_parent + R_B,parent p_k. With
/// `unrotated_axes` the pitfall of docs/design.md 2.7 instead: a child's axis taken in B,
/// R_Bk = Exp(a_k theta_k) R_B,parent (to show that the comparison would see it).
void Pose(const HingedBody& b,
          const Eigen::VectorXd& theta,
          int k,
          Mat3& R,
          Vec3& o,
          bool unrotated_axes = false) {
  const Panel& p = b.panels[static_cast<std::size_t>(k)];
  Mat3 R_parent = Mat3::Identity();
  Vec3 o_parent = Vec3::Zero();
  if (p.parent >= 0) Pose(b, theta, p.parent, R_parent, o_parent, unrotated_axes);
  const Mat3 turn = math::ExpSO3(p.hinge_axis_B * theta[k]);
  R = unrotated_axes ? Mat3(turn * R_parent) : Mat3(R_parent * turn);
  o = o_parent + R_parent * p.hinge_point_B;
}

/// Every part's particles in B at hinge angles theta.
std::vector<Particle> Particles(const HingedBody& b,
                                const Eigen::VectorXd& theta,
                                bool unrotated_axes = false) {
  std::vector<Particle> out;
  for (const Vec3& s : ParticleOffsets(b.hub.body.mass, b.hub.body.inertia_cm)) {
    out.push_back({b.hub.body.mass / 6.0, b.hub.com_B + s});
  }
  for (std::size_t k = 0; k < b.panels.size(); ++k) {
    const Panel& p = b.panels[k];
    Mat3 R;
    Vec3 o;
    Pose(b, theta, static_cast<int>(k), R, o, unrotated_axes);
    for (const Vec3& s : ParticleOffsets(p.body.mass, p.body.inertia_cm)) {
      out.push_back({p.body.mass / 6.0, o + R * (p.com_offset_B + s)});
    }
  }
  return out;
}

Vec3 Com(const std::vector<Particle>& ps) {
  double M = 0.0;
  Vec3 mx = Vec3::Zero();
  for (const Particle& p : ps) {
    M += p.mass;
    mx += p.mass * p.x;
  }
  return mx / M;
}

Mat3 ParticleInertia(const std::vector<Particle>& ps) {
  const Vec3 c = Com(ps);
  Mat3 J = Mat3::Zero();
  for (const Particle& p : ps) J += p.mass * S(p.x - c);
  return J;
}

/// f'(0) by the 4th-order central difference.
template <typename T, typename F>
T CentralDifference(const F& f, double h) {
  const T d = (f(-2.0 * h) - 8.0 * f(-h) + 8.0 * f(h) - f(2.0 * h)) / (12.0 * h);
  return d;
}

TEST(PanelTreeTest, BranchedTreesWithSkewAxesMatchParticles) {
  std::mt19937_64 rng(kSeed);
  double worst_J = 0.0, worst_Jdot = 0.0, worst_h = 0.0, worst_T = 0.0;
  int deep = 0, branched = 0, listed_before_parent = 0;
  for (int trial = 0; trial < kRandomTrees; ++trial) {
    const HingedBody b = RandomTree(rng);
    const std::size_t n = b.panels.size();
    const Eigen::VectorXd theta0 = RandomVector(rng, n, M_PI);
    const Eigen::VectorXd theta_dot = RandomVector(rng, n, 2.0);
    const MassProperties mp = ComputeMassProperties(b, theta0, theta_dot);
    const auto particles_at = [&](double t) {
      return Particles(b, Eigen::VectorXd(theta0 + theta_dot * t));
    };
    const std::vector<Particle> p0 = particles_at(0.0);
    const Vec3 c0 = Com(p0);
    const double h = kFiniteDifferenceStep;
    const double rate_scale = theta_dot.cwiseAbs().maxCoeff();

    const Mat3 J = ParticleInertia(p0);
    const double err_J = (mp.J_B - J).norm() / J.norm();
    EXPECT_LT(err_J, kParticleInertiaTolerance) << "trial " << trial << "\n"
                                                << mp.J_B << "\nvs\n"
                                                << J;
    EXPECT_LT((mp.com_B - c0).norm(), kRoundoffTolerance * (1.0 + c0.norm())) << trial;

    const Mat3 Jdot = CentralDifference<Mat3>(
        [&](double t) -> Mat3 { return ParticleInertia(particles_at(t)); }, h);
    const double err_Jdot = (mp.Jdot_B - Jdot).norm() / (J.norm() * rate_scale);
    EXPECT_LT(err_Jdot, kJdotTolerance) << "trial " << trial << "\n"
                                        << mp.Jdot_B << "\nvs\n"
                                        << Jdot;
    const Vec3 com_rate =
        CentralDifference<Vec3>([&](double t) -> Vec3 { return Com(particles_at(t)); }, h);
    EXPECT_LT((mp.com_rate_B - com_rate).norm(), kMomentumTolerance * rate_scale) << trial;

    // Particle velocities relative to the system CoM, seen in B.
    Vec3 h_rel = Vec3::Zero();
    double two_T = 0.0;
    for (std::size_t i = 0; i < p0.size(); ++i) {
      const Vec3 rho_dot = CentralDifference<Vec3>(
          [&](double t) -> Vec3 {
            const std::vector<Particle> pt = particles_at(t);
            return pt[i].x - Com(pt);
          },
          h);
      h_rel += p0[i].mass * (p0[i].x - c0).cross(rho_dot);
      two_T += p0[i].mass * rho_dot.squaredNorm();
    }
    const double err_h = (mp.h_rel_B - h_rel).norm() / (J.norm() * rate_scale);
    EXPECT_LT(err_h, kMomentumTolerance)
        << "trial " << trial << ": " << mp.h_rel_B.transpose() << " vs " << h_rel.transpose();
    const double err_T = std::abs(mp.relative_kinetic_energy - 0.5 * two_T) / (0.5 * two_T);
    EXPECT_LT(err_T, kEnergyTolerance) << "trial " << trial;
    worst_J = std::max(worst_J, err_J);
    worst_Jdot = std::max(worst_Jdot, err_Jdot);
    worst_h = std::max(worst_h, err_h);
    worst_T = std::max(worst_T, err_T);

    // The trees are what they should be: deep panels whose axes are turned in B, so that
    // forgetting R_B,parent on a child's axis would be seen; branching; parents listed
    // after their children.
    const Mat3 J_unrotated = ParticleInertia(Particles(b, theta0, true));
    deep += (J_unrotated - J).norm() > 1e3 * kRoundoffTolerance * J.norm() ? 1 : 0;
    std::vector<int> children(n, 0);
    for (std::size_t k = 0; k < n; ++k) {
      const Panel& p = b.panels[k];
      if (p.parent < 0) continue;
      ++children[static_cast<std::size_t>(p.parent)];
      if (p.parent > static_cast<int>(k)) ++listed_before_parent;
    }
    branched += *std::max_element(children.begin(), children.end()) >= 2 ? 1 : 0;
  }
  EXPECT_GT(deep, kRandomTrees * 9 / 10);  // measured 200 of 200
  EXPECT_GT(branched, kRandomTrees / 4);   // measured 114
  EXPECT_GT(listed_before_parent, kRandomTrees / 4);
  std::ostringstream os;
  os << "J " << worst_J << ", Jdot " << worst_Jdot << ", h_rel " << worst_h << ", T_rel " << worst_T
     << " (" << deep << " deep, " << branched << " branched trees)";
  std::cout << "measured worst relative errors: " << os.str() << std::endl;
  RecordProperty("worst_relative_errors", os.str());
}

TEST(PanelTreeTest, TheListingOrderDoesNotMatter) {
  // Reversing the panel list (parents remapped, angles and rates permuted with it) gives
  // the same mass properties to rounding.
  std::mt19937_64 rng(kSeed + 1);
  for (int trial = 0; trial < 50; ++trial) {
    const HingedBody b = RandomTree(rng);
    const std::size_t n = b.panels.size();
    const Eigen::VectorXd theta = RandomVector(rng, n, M_PI);
    const Eigen::VectorXd theta_dot = RandomVector(rng, n, 2.0);
    HingedBody r = b;
    Eigen::VectorXd r_theta(theta.size()), r_theta_dot(theta.size());
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t to = n - 1 - k;
      r.panels[to] = b.panels[k];
      if (b.panels[k].parent >= 0) {
        r.panels[to].parent = static_cast<int>(n - 1) - b.panels[k].parent;
      }
      r_theta[static_cast<Eigen::Index>(to)] = theta[static_cast<Eigen::Index>(k)];
      r_theta_dot[static_cast<Eigen::Index>(to)] = theta_dot[static_cast<Eigen::Index>(k)];
    }
    r = ValidatedHingedBody(r, "reversed");
    const MassProperties m1 = ComputeMassProperties(b, theta, theta_dot);
    const MassProperties m2 = ComputeMassProperties(r, r_theta, r_theta_dot);
    const double scale = m1.J_B.norm() * (1.0 + theta_dot.cwiseAbs().maxCoeff());
    EXPECT_LT((m1.J_B - m2.J_B).norm(), kRoundoffTolerance * scale) << trial;
    EXPECT_LT((m1.Jdot_B - m2.Jdot_B).norm(), kRoundoffTolerance * scale) << trial;
    EXPECT_LT((m1.h_rel_B - m2.h_rel_B).norm(), kRoundoffTolerance * scale) << trial;
    EXPECT_LT((m1.com_B - m2.com_B).norm(), kRoundoffTolerance) << trial;
    EXPECT_NEAR(m1.relative_kinetic_energy, m2.relative_kinetic_energy, kRoundoffTolerance * scale)
        << trial;
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::model
