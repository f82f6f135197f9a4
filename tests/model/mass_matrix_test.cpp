#include "deploysim/model/mass_matrix.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "deploysim/model/mass_properties.h"

namespace deploysim::model {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Mat3;
using math::Vec3;

// Tolerances, relative to the scale named at each use.
/// Two ways of summing the same kinetic energy (mass matrix vs part by part): rounding.
constexpr double kRoundoffTolerance = 1e-13;
/// dT/dtheta against Richardson-extrapolated central differences of T (step 1e-3 rad,
/// error O(h^4) ~ 1e-12 of the energy scale; measured worst case 1.9e-12 over the cases).
constexpr double kGradientTolerance = 1e-11;
constexpr int kRandomCases = 100;
constexpr std::uint64_t kSeed = 20261202;

Vec3 RandomVec(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Vec3(u(rng), u(rng), u(rng));
}

/// A random valid inertia about the CoM: R diag(m) R^T with triangle-valid moments.
Mat3 RandomInertia(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(0.3, 1.0);
  const double a = u(rng), b = u(rng);
  const Vec3 m(a + b, b + 0.5 * a, a + 0.7 * b);  // each <= sum of the other two
  const Mat3 R = Eigen::Quaterniond(Eigen::Vector4d(RandomVec(rng, 1).x(), RandomVec(rng, 1).y(),
                                                    RandomVec(rng, 1).z(), 0.7))
                     .normalized()
                     .toRotationMatrix();
  return scale * R * m.asDiagonal() * R.transpose();
}

/// A random tree of n panels with skew hinge axes; panel k's parent is the hub or an
/// earlier panel, listed in a shuffled order so that parents may come after children.
HingedBody RandomTree(std::mt19937_64& rng, int n) {
  HingedBody body;
  body.hub.body.mass = 50.0;
  body.hub.body.inertia_cm = RandomInertia(rng, 10.0);
  body.hub.com_B = RandomVec(rng, 0.1);
  std::vector<int> perm(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) perm[static_cast<std::size_t>(k)] = k;
  std::shuffle(perm.begin(), perm.end(), rng);
  body.panels.resize(static_cast<std::size_t>(n));
  std::uniform_int_distribution<int> coin(0, 2);
  for (int j = 0; j < n; ++j) {
    Panel& p = body.panels[static_cast<std::size_t>(perm[static_cast<std::size_t>(j)])];
    p.name = "p" + std::to_string(j);
    p.body.mass = 2.0 + std::abs(RandomVec(rng, 3).x());
    p.body.inertia_cm = RandomInertia(rng, 0.5);
    // Parent: the hub, or the panel placed just before (chains and branches).
    p.parent = (j == 0 || coin(rng) == 0)
                   ? -1
                   : perm[static_cast<std::size_t>(j - 1 - (coin(rng) == 2 && j >= 2 ? 1 : 0))];
    p.hinge_point_B = RandomVec(rng, 0.6);
    p.hinge_axis_B = RandomVec(rng, 1.0).normalized();
    p.com_offset_B = RandomVec(rng, 0.5);
  }
  return ValidatedHingedBody(body, "random tree");
}

double Energy(const HingedBody& body,
              const PanelTree& tree,
              const Eigen::VectorXd& theta,
              const Vec3& w,
              const Eigen::VectorXd& theta_dot) {
  TreePose pose;
  ComputePose(body, tree, theta, pose);
  TreeVelocity vel;
  ComputeVelocity(body, tree, pose, w, theta_dot, vel);
  return KineticEnergy(pose, vel);
}

TEST(MassMatrixTest, QuadraticFormIsTheKineticEnergy) {
  std::mt19937_64 rng(kSeed);
  for (int c = 0; c < kRandomCases; ++c) {
    const int n = 1 + c % 5;
    const HingedBody body = RandomTree(rng, n);
    const PanelTree tree(body);
    const Eigen::VectorXd theta = Eigen::VectorXd::Random(n) * 3.0;
    const Eigen::VectorXd theta_dot = Eigen::VectorXd::Random(n);
    const Vec3 w = RandomVec(rng, 1.0);
    TreePose pose;
    ComputePose(body, tree, theta, pose);
    std::vector<int> all(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) all[static_cast<std::size_t>(k)] = k;
    Eigen::MatrixXd M;
    ComputeMassMatrix(body, tree, pose, all, M);
    Eigen::VectorXd v(3 + n);
    v << w, theta_dot;
    const double T_matrix = 0.5 * v.dot(M * v);
    const double T_parts = Energy(body, tree, theta, w, theta_dot);
    EXPECT_NEAR(T_matrix, T_parts, kRoundoffTolerance * T_parts) << "case " << c;
    EXPECT_LT((M - M.transpose()).norm(), kRoundoffTolerance * M.norm());
    EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(M).info(), Eigen::Success) << "case " << c;
  }
}

TEST(MassMatrixTest, SubsetOfColumnsIsTheSubmatrix) {
  std::mt19937_64 rng(kSeed + 1);
  const HingedBody body = RandomTree(rng, 5);
  const PanelTree tree(body);
  const Eigen::VectorXd theta = Eigen::VectorXd::Random(5);
  TreePose pose;
  ComputePose(body, tree, theta, pose);
  Eigen::MatrixXd M, Ms;
  ComputeMassMatrix(body, tree, pose, {0, 1, 2, 3, 4}, M);
  ComputeMassMatrix(body, tree, pose, {3, 1}, Ms);
  const int idx[5] = {0, 1, 2, 3 + 3, 3 + 1};
  for (int a = 0; a < 5; ++a) {
    for (int b = 0; b < 5; ++b) {
      EXPECT_NEAR(Ms(a, b), M(idx[a], idx[b]), kRoundoffTolerance * M.norm());
    }
  }
}

TEST(MassMatrixTest, BlocksAgreeWithMassPropertiesForHubChildren) {
  // Single-level bodies: J_B, h_rel_B = Bm theta' and T_rel = 1/2 theta'^T M_tt theta'
  // against model::ComputeMassProperties (independent code, docs/design.md 2.5).
  std::mt19937_64 rng(kSeed + 2);
  for (int c = 0; c < 20; ++c) {
    const int n = 1 + c % 4;
    HingedBody body = RandomTree(rng, n);
    for (Panel& p : body.panels) p.parent = -1;
    const PanelTree tree(body);
    const Eigen::VectorXd theta = Eigen::VectorXd::Random(n) * 3.0;
    const Eigen::VectorXd theta_dot = Eigen::VectorXd::Random(n);
    TreePose pose;
    ComputePose(body, tree, theta, pose);
    std::vector<int> all(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) all[static_cast<std::size_t>(k)] = k;
    Eigen::MatrixXd M;
    ComputeMassMatrix(body, tree, pose, all, M);
    const MassProperties mp = ComputeMassProperties(body, theta, theta_dot);
    const double J_scale = mp.J_B.norm();
    EXPECT_LT((M.block<3, 3>(0, 0) - mp.J_B).norm(), kRoundoffTolerance * J_scale);
    const Vec3 h = M.block(0, 3, 3, n) * theta_dot;
    EXPECT_LT((h - mp.h_rel_B).norm(), kRoundoffTolerance * J_scale * theta_dot.norm());
    const double T_rel = 0.5 * theta_dot.dot(M.block(3, 3, n, n) * theta_dot);
    EXPECT_NEAR(T_rel, mp.relative_kinetic_energy, kRoundoffTolerance * J_scale);
    EXPECT_LT((pose.com_B - mp.com_B).norm(), 1e-15 * 10.0);
  }
}

TEST(MassMatrixTest, GradientMatchesDifferencesOfTheEnergy) {
  std::mt19937_64 rng(kSeed + 3);
  double worst = 0.0;
  for (int c = 0; c < kRandomCases; ++c) {
    const int n = 1 + c % 5;
    const HingedBody body = RandomTree(rng, n);
    const PanelTree tree(body);
    const Eigen::VectorXd theta = Eigen::VectorXd::Random(n) * 3.0;
    const Eigen::VectorXd theta_dot = Eigen::VectorXd::Random(n);
    const Vec3 w = RandomVec(rng, 1.0);
    TreePose pose;
    ComputePose(body, tree, theta, pose);
    TreeVelocity vel;
    ComputeVelocity(body, tree, pose, w, theta_dot, vel);
    std::vector<int> all(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) all[static_cast<std::size_t>(k)] = k;
    Eigen::VectorXd grad;
    KineticEnergyGradient(tree, pose, vel, all, grad);
    const double scale = KineticEnergy(pose, vel);
    for (int k = 0; k < n; ++k) {
      auto T = [&](double d) {
        Eigen::VectorXd th = theta;
        th[k] += d;
        return Energy(body, tree, th, w, theta_dot);
      };
      constexpr double h = 1e-3;
      const double d1 = (T(h) - T(-h)) / (2 * h);
      const double d2 = (T(2 * h) - T(-2 * h)) / (4 * h);
      const double richardson = (4.0 * d1 - d2) / 3.0;
      const double err = std::abs(grad[k] - richardson) / scale;
      worst = std::max(worst, err);
      EXPECT_LT(err, kGradientTolerance) << "case " << c << " hinge " << k;
    }
  }
  std::printf("worst relative gradient error: %.3g\n", worst);
}

TEST(MassMatrixTest, CycleIsRefused) {
  HingedBody body;
  body.hub.body.mass = 1.0;
  body.hub.body.inertia_cm = Mat3::Identity();
  body.panels.resize(2);
  body.panels[0].parent = 1;
  body.panels[1].parent = 0;
  EXPECT_THROW(PanelTree{body}, std::invalid_argument);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::model
