#include "deploysim/model/mass_properties.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <new>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "deploysim/math/inertia.h"
#include "deploysim/math/so3.h"

// Heap-allocation counter for the no-allocation test: every (unaligned) operator new and
// delete of this test executable is replaced, so that all of them pair malloc with free
// (AddressSanitizer checks the pairing).
// Counting allocations replaces the global operator new, which AddressSanitizer also
// does: the count (and its test) exists only in builds without ASan.
#if defined(__SANITIZE_ADDRESS__)
#define DEPLOYSIM_COUNT_ALLOCATIONS 0
#else
#define DEPLOYSIM_COUNT_ALLOCATIONS 1
#endif

#if DEPLOYSIM_COUNT_ALLOCATIONS
namespace {
std::atomic<long> g_allocations{0};
void* CountedMalloc(std::size_t size) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}
}  // namespace

void* operator new(std::size_t size) {
  if (void* p = CountedMalloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  if (void* p = CountedMalloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return CountedMalloc(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return CountedMalloc(size);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
#endif  // DEPLOYSIM_COUNT_ALLOCATIONS

namespace deploysim::model {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Mat3;
using math::Vec3;

// Tolerances, relative to the scale named at each use.
constexpr double kRoundoffTolerance = 1e-13;         // Two evaluations of the same sums.
constexpr double kFiniteDifferenceTolerance = 1e-9;  // 4th-order central differences.
constexpr double kFiniteDifferenceStep = 1e-3;       // [s] along theta(t) = theta0 + thetadot t.
/// Kinetic energy against 4th-order differences of the parts' inertial motion (measured
/// worst case over the random cases: 4.4e-12, and 2.6e-11 for T_rel alone).
constexpr double kEnergyFiniteDifferenceTolerance = 1e-10;
/// Rotating the whole model changes the rounding of every sum: a looser roundoff bound.
constexpr double kRotatedRoundoffTolerance = 1e-11;
/// The CoM-shift terms must be at least this large relative to J for the CoM-shift test
/// to be able to fail.
constexpr double kNonNegligibleShift = 1e-4;
constexpr int kRandomCases = 200;
constexpr std::uint64_t kSeed = 20240607;

Mat3 S(const Vec3& d) { return d.squaredNorm() * Mat3::Identity() - d * d.transpose(); }

/// Random unit vector whose components are all at most 0.9 in magnitude (so the hinge
/// axis is not along a hub axis).
Vec3 RandomOffAxisUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  for (;;) {
    const Vec3 v(n(rng), n(rng), n(rng));
    const double norm = v.norm();
    if (norm < 1e-3) continue;
    const Vec3 u = v / norm;
    if (u.cwiseAbs().maxCoeff() <= 0.9) return u;
  }
}

Mat3 RandomRotation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  return math::ExpSO3(Vec3(u(rng), u(rng), u(rng)));
}

/// A random valid hub with 1-4 panels: random masses, box sizes, panel orientations at
/// theta = 0, hinge points, off-axis hinge axes and CoM offsets; hub CoM off the origin.
HingedBody RandomBody(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  HingedBody b;
  b.hub.body.mass = 50.0 + 50.0 * u(rng);
  const Mat3 R_hub = RandomRotation(rng);
  b.hub.body.inertia_cm =
      R_hub * BoxInertia(b.hub.body.mass, Vec3(0.3 + u(rng), 0.3 + u(rng), 0.3 + u(rng))) *
      R_hub.transpose();
  b.hub.com_B = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * 0.2;
  const int n = 1 + static_cast<int>(u(rng) * 4.0);
  for (int k = 0; k < n; ++k) {
    Panel p;
    p.name = "panel" + std::to_string(k);
    p.body.mass = 1.0 + 9.0 * u(rng);
    const Mat3 Q = RandomRotation(rng);
    p.body.inertia_cm =
        Q * BoxInertia(p.body.mass, Vec3(0.2 + u(rng), 0.2 + u(rng), 0.01 + 0.05 * u(rng))) *
        Q.transpose();
    p.hinge_point_B = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * 1.2;
    p.hinge_axis_B = RandomOffAxisUnit(rng) * (0.5 + u(rng));  // normalized by validation
    p.com_offset_B = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * 1.5;
    b.panels.push_back(p);
  }
  return ValidatedHingedBody(b, "random body");
}

Eigen::VectorXd RandomVector(std::mt19937_64& rng, std::size_t n, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Eigen::VectorXd v(static_cast<Eigen::Index>(n));
  for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = u(rng);
  return v;
}

/// One rigid part seen in B, computed independently of mass_properties.cc (ExpSO3 for
/// the rotations, positions from the B origin).
struct Part {
  double m;
  Mat3 I_B;    // inertia about its CoM, B axes
  Vec3 x;      // CoM in B
  Vec3 x_dot;  // CoM rate seen in B
  Vec3 w_rel;  // angular velocity relative to B
};

std::vector<Part> Parts(const HingedBody& b,
                        const Eigen::VectorXd& theta,
                        const Eigen::VectorXd& theta_dot) {
  std::vector<Part> parts;
  parts.push_back(
      {b.hub.body.mass, b.hub.body.inertia_cm, b.hub.com_B, Vec3::Zero(), Vec3::Zero()});
  for (std::size_t k = 0; k < b.panels.size(); ++k) {
    const Panel& p = b.panels[k];
    const Eigen::Index i = static_cast<Eigen::Index>(k);
    const Mat3 R = math::ExpSO3(p.hinge_axis_B * theta[i]);
    const Vec3 r = R * p.com_offset_B;
    parts.push_back({p.body.mass, R * p.body.inertia_cm * R.transpose(), p.hinge_point_B + r,
                     theta_dot[i] * p.hinge_axis_B.cross(r), theta_dot[i] * p.hinge_axis_B});
  }
  return parts;
}

Vec3 SystemCom(const std::vector<Part>& parts) {
  double M = 0.0;
  Vec3 mx = Vec3::Zero();
  for (const Part& p : parts) {
    M += p.m;
    mx += p.m * p.x;
  }
  return mx / M;
}

/// H_direct = sum_i [ I_i (w + w_rel_i) + m_i rho_i x (w x rho_i + rho_i') ] about the
/// system CoM, with rho_i' the part's CoM rate in B (the CoM-shift part cancels).
Vec3 DirectMomentum(const std::vector<Part>& parts, const Vec3& w) {
  const Vec3 c = SystemCom(parts);
  Vec3 H = Vec3::Zero();
  for (const Part& p : parts) {
    const Vec3 rho = p.x - c;
    H += p.I_B * (w + p.w_rel) + p.m * rho.cross(w.cross(rho) + p.x_dot);
  }
  return H;
}

/// f'(0) by the 4th-order central difference along theta(t) = theta0 + thetadot t.
template <typename T, typename F>
T CentralDifference(const F& f, double h) {
  const T d = (f(-2.0 * h) - 8.0 * f(-h) + 8.0 * f(h) - f(2.0 * h)) / (12.0 * h);
  return d;
}

TEST(MassPropertiesTest, JdotAndComRateMatchFiniteDifferences) {
  std::mt19937_64 rng(kSeed);
  for (int trial = 0; trial < kRandomCases; ++trial) {
    const HingedBody b = RandomBody(rng);
    const Eigen::VectorXd theta0 = RandomVector(rng, b.panels.size(), M_PI);
    const Eigen::VectorXd theta_dot = RandomVector(rng, b.panels.size(), 2.0);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(theta0.size());
    const MassProperties mp = ComputeMassProperties(b, theta0, theta_dot);
    const auto at = [&](double t) {
      const Eigen::VectorXd theta = theta0 + theta_dot * t;
      return ComputeMassProperties(b, theta, zero);
    };
    const Mat3 Jdot_fd =
        CentralDifference<Mat3>([&](double t) -> Mat3 { return at(t).J_B; }, kFiniteDifferenceStep);
    const Vec3 com_rate_fd = CentralDifference<Vec3>([&](double t) -> Vec3 { return at(t).com_B; },
                                                     kFiniteDifferenceStep);
    const double rate_scale = theta_dot.cwiseAbs().maxCoeff();
    EXPECT_LT((mp.Jdot_B - Jdot_fd).norm(), kFiniteDifferenceTolerance * mp.J_B.norm() * rate_scale)
        << "trial " << trial << "\n"
        << mp.Jdot_B << "\nvs\n"
        << Jdot_fd;
    EXPECT_LT((mp.com_rate_B - com_rate_fd).norm(), kFiniteDifferenceTolerance * rate_scale)
        << "trial " << trial;
    // J_B itself against the independent parallel-axis sum about the system CoM.
    const std::vector<Part> parts = Parts(b, theta0, theta_dot);
    const Vec3 c = SystemCom(parts);
    Mat3 J_direct = Mat3::Zero();
    for (const Part& p : parts) J_direct += p.I_B + p.m * S(p.x - c);
    EXPECT_LT((mp.J_B - J_direct).norm(), kRoundoffTolerance * J_direct.norm()) << trial;
    EXPECT_LT((mp.com_B - c).norm(), kRoundoffTolerance * (1.0 + c.norm())) << trial;
    EXPECT_EQ(mp.J_B, mp.J_B.transpose());
    EXPECT_EQ(mp.Jdot_B, mp.Jdot_B.transpose());
  }
}

TEST(MassPropertiesTest, RelativeMomentumMatchesFiniteDifferencesOfTheGeometry) {
  // h_rel = sum_k I_k w_k + sum_i m_i rho_i x rho_i', with w_k from the finite difference
  // of the panel orientation (LogSO3) and rho_i' from that of rho_i = x_i - c.
  std::mt19937_64 rng(kSeed + 1);
  for (int trial = 0; trial < kRandomCases; ++trial) {
    const HingedBody b = RandomBody(rng);
    const Eigen::VectorXd theta0 = RandomVector(rng, b.panels.size(), M_PI);
    const Eigen::VectorXd theta_dot = RandomVector(rng, b.panels.size(), 2.0);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(theta0.size());
    const auto parts_at = [&](double t) {
      return Parts(b, Eigen::VectorXd(theta0 + theta_dot * t), zero);
    };
    const std::vector<Part> p0 = parts_at(0.0);
    const Vec3 c0 = SystemCom(p0);
    const double h = kFiniteDifferenceStep;
    Vec3 h_fd = Vec3::Zero();
    for (std::size_t i = 0; i < p0.size(); ++i) {
      const auto rho = [&](double t) -> Vec3 {
        const std::vector<Part> pt = parts_at(t);
        return pt[i].x - SystemCom(pt);
      };
      const Vec3 rho_dot = CentralDifference<Vec3>(rho, h);
      h_fd += p0[i].m * (p0[i].x - c0).cross(rho_dot);
      if (i == 0) continue;
      // Orientation at t: R(t) = ExpSO3(a theta(t)) (times the fixed theta = 0 pose).
      const Panel& panel = b.panels[i - 1];
      const Eigen::Index k = static_cast<Eigen::Index>(i - 1);
      const Mat3 R_minus = math::ExpSO3(panel.hinge_axis_B * (theta0[k] - theta_dot[k] * h));
      const Mat3 R_plus = math::ExpSO3(panel.hinge_axis_B * (theta0[k] + theta_dot[k] * h));
      const Vec3 w_fd = math::LogSO3(R_plus * R_minus.transpose()) / (2.0 * h);
      h_fd += p0[i].I_B * w_fd;
    }
    const MassProperties mp = ComputeMassProperties(b, theta0, theta_dot);
    const double scale = mp.J_B.norm() * theta_dot.cwiseAbs().maxCoeff();
    EXPECT_LT((mp.h_rel_B - h_fd).norm(), kFiniteDifferenceTolerance * scale)
        << "trial " << trial << ": " << mp.h_rel_B.transpose() << " vs " << h_fd.transpose();
  }
}

TEST(MassPropertiesTest, TotalMomentumMatchesDirectSumOverParts) {
  // J_B w + h_rel_B = sum_i [ R_i I_i R_i^T (w + thetadot_i a_i) + m_i rho_i x (w x rho_i + rho_i')
  // ].
  std::mt19937_64 rng(kSeed + 2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < kRandomCases; ++trial) {
    const HingedBody b = RandomBody(rng);
    const Eigen::VectorXd theta = RandomVector(rng, b.panels.size(), M_PI);
    const Eigen::VectorXd theta_dot = RandomVector(rng, b.panels.size(), 2.0);
    const Vec3 w(u(rng), u(rng), u(rng));
    const MassProperties mp = ComputeMassProperties(b, theta, theta_dot);
    const Vec3 H_model = mp.J_B * w + mp.h_rel_B;
    const Vec3 H_direct = DirectMomentum(Parts(b, theta, theta_dot), w);
    const double err = (H_model - H_direct).norm() / H_direct.norm();
    worst = std::max(worst, err);
    EXPECT_LT(err, kRoundoffTolerance)
        << "trial " << trial << ": " << H_model.transpose() << " vs " << H_direct.transpose();
    // And the relative part alone (w = 0) against its direct sum.
    const Vec3 h_direct = DirectMomentum(Parts(b, theta, theta_dot), Vec3::Zero());
    EXPECT_LT((mp.h_rel_B - h_direct).norm(), kRoundoffTolerance * H_direct.norm()) << trial;
  }
  std::ostringstream os;
  os << worst;
  RecordProperty("worst_relative_error", os.str());
}

/// Kinetic energy of the whole system, independently of mass_properties.cc: the body B
/// turns at constant w (in B) from a random attitude, the hinges at constant rates; every
/// part's CoM velocity relative to the system CoM and its angular velocity are taken in
/// the inertial frame N by 4th-order differences of its position and orientation in
/// time (Richardson on LogSO3 for the orientation), and
///   T = sum_i 1/2 m_i |v_i|^2 + 1/2 W_i^T (R_Ni I_i R_Ni^T) W_i.
double FiniteDifferenceKineticEnergy(const HingedBody& b,
                                     const Mat3& R_NB0,
                                     const Vec3& w,
                                     const Eigen::VectorXd& theta0,
                                     const Eigen::VectorXd& theta_dot,
                                     double h) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(theta0.size());
  const auto R_NB = [&](double t) -> Mat3 { return R_NB0 * math::ExpSO3(w * t); };
  // Position in N of part i's CoM relative to the system CoM, and orientation of part i.
  const auto position = [&](std::size_t i, double t) -> Vec3 {
    const std::vector<Part> pt = Parts(b, Eigen::VectorXd(theta0 + theta_dot * t), zero);
    return R_NB(t) * (pt[i].x - SystemCom(pt));
  };
  const auto orientation = [&](std::size_t i, double t) -> Mat3 {
    if (i == 0) return R_NB(t);
    const Eigen::Index k = static_cast<Eigen::Index>(i - 1);
    return R_NB(t) * math::ExpSO3(b.panels[i - 1].hinge_axis_B * (theta0[k] + theta_dot[k] * t));
  };
  const auto angular_velocity = [&](std::size_t i, double step) -> Vec3 {
    return math::LogSO3(orientation(i, step) * orientation(i, -step).transpose()) / (2.0 * step);
  };
  const std::vector<Part> p0 = Parts(b, theta0, zero);
  double T = 0.0;
  for (std::size_t i = 0; i < p0.size(); ++i) {
    const Vec3 v = CentralDifference<Vec3>([&](double t) -> Vec3 { return position(i, t); }, h);
    // The error of the symmetric difference of the orientation is even in the step.
    const Vec3 W = (4.0 * angular_velocity(i, h) - angular_velocity(i, 2.0 * h)) / 3.0;
    // p0[i].I_B is the inertia in B axes at theta0; in N it is R_NB I_B R_NB^T.
    const Mat3 I_N = R_NB0 * p0[i].I_B * R_NB0.transpose();
    T += 0.5 * p0[i].m * v.squaredNorm() + 0.5 * W.dot(I_N * W);
  }
  return T;
}

TEST(MassPropertiesTest, TotalKineticEnergyMatchesFiniteDifferencesOfTheMotion) {
  // T = 1/2 w.J w + w.h_rel + T_rel (docs/design.md 2.5; dynamics::TotalKineticEnergy) against
  // the energy of the parts' inertial motion.
  std::mt19937_64 rng(kSeed + 7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  double worst_rel = 0.0;
  for (int trial = 0; trial < kRandomCases; ++trial) {
    const HingedBody b = RandomBody(rng);
    const Eigen::VectorXd theta = RandomVector(rng, b.panels.size(), M_PI);
    const Eigen::VectorXd theta_dot = RandomVector(rng, b.panels.size(), 2.0);
    const Vec3 w(u(rng), u(rng), u(rng));
    const Mat3 R_NB0 = RandomRotation(rng);
    const MassProperties mp = ComputeMassProperties(b, theta, theta_dot);
    const double T_model = 0.5 * w.dot(mp.J_B * w) + w.dot(mp.h_rel_B) + mp.relative_kinetic_energy;
    const double T_fd =
        FiniteDifferenceKineticEnergy(b, R_NB0, w, theta, theta_dot, kFiniteDifferenceStep);
    const double err = std::abs(T_model - T_fd) / T_fd;
    worst = std::max(worst, err);
    EXPECT_LT(err, kEnergyFiniteDifferenceTolerance)
        << "trial " << trial << ": " << T_model << " vs " << T_fd;
    // The relative part alone (B at rest in N): T = T_rel.
    const double T_rel_fd = FiniteDifferenceKineticEnergy(b, R_NB0, Vec3::Zero(), theta, theta_dot,
                                                          kFiniteDifferenceStep);
    const double err_rel = std::abs(mp.relative_kinetic_energy - T_rel_fd) / T_rel_fd;
    worst_rel = std::max(worst_rel, err_rel);
    EXPECT_LT(err_rel, kEnergyFiniteDifferenceTolerance)
        << "trial " << trial << ": T_rel " << mp.relative_kinetic_energy << " vs " << T_rel_fd;
    // Without the CoM-shift term -c' in rho_i' (rates seen from the hub CoM) T_rel is
    // wrong by 1/2 M |c'|^2, far above the tolerance: the test can see it.
    const double shift = 0.5 * mp.mass * mp.com_rate_B.squaredNorm();
    EXPECT_GT(shift, 1e3 * kEnergyFiniteDifferenceTolerance * T_rel_fd) << "trial " << trial;
  }
  std::ostringstream os;
  os << worst << " (relative part alone: " << worst_rel << ")";
  RecordProperty("worst_relative_error", os.str());
}

TEST(MassPropertiesTest, HubFramePositionsAreWrongByTheComShift) {
  // docs/design.md 2.5: measuring from the B origin instead of the system CoM c is wrong by
  // M S(c) in J and by M c x c' in h_rel. The geometry makes the shift large.
  std::mt19937_64 rng(kSeed + 3);
  for (int trial = 0; trial < kRandomCases; ++trial) {
    const HingedBody b = RandomBody(rng);
    const Eigen::VectorXd theta = RandomVector(rng, b.panels.size(), M_PI);
    const Eigen::VectorXd theta_dot = RandomVector(rng, b.panels.size(), 2.0);
    const MassProperties mp = ComputeMassProperties(b, theta, theta_dot);
    const std::vector<Part> parts = Parts(b, theta, theta_dot);
    Mat3 J_origin = Mat3::Zero();
    Vec3 h_origin = Vec3::Zero();
    for (const Part& p : parts) {
      J_origin += p.I_B + p.m * S(p.x);
      h_origin += p.I_B * p.w_rel + p.m * p.x.cross(p.x_dot);
    }
    const Mat3 J_shift = mp.mass * S(mp.com_B);
    const Vec3 h_shift = mp.mass * mp.com_B.cross(mp.com_rate_B);
    EXPECT_LT((J_origin - mp.J_B - J_shift).norm(), kRoundoffTolerance * J_origin.norm());
    EXPECT_LT((h_origin - mp.h_rel_B - h_shift).norm(),
              kRoundoffTolerance * (h_origin.norm() + J_origin.norm()));
    // The shift is not negligible here, so this test fails if it were dropped.
    EXPECT_GT(J_shift.norm(), kNonNegligibleShift * mp.J_B.norm()) << trial;
  }
}

TEST(MassPropertiesTest, EquivariantUnderRotationOfTheWholeGeometry) {
  // Rotating every vector and tensor of the model by Q rotates J by Q J Q^T and h by Q h.
  std::mt19937_64 rng(kSeed + 4);
  for (int trial = 0; trial < 50; ++trial) {
    const HingedBody b = RandomBody(rng);
    const Mat3 Q = RandomRotation(rng);
    HingedBody q = b;
    q.hub.body.inertia_cm = Q * b.hub.body.inertia_cm * Q.transpose();
    q.hub.com_B = Q * b.hub.com_B;
    for (Panel& p : q.panels) {
      p.body.inertia_cm = Q * p.body.inertia_cm * Q.transpose();
      p.hinge_point_B = Q * p.hinge_point_B;
      p.hinge_axis_B = Q * p.hinge_axis_B;
      p.com_offset_B = Q * p.com_offset_B;
    }
    q = ValidatedHingedBody(q, "rotated");
    const Eigen::VectorXd theta = RandomVector(rng, b.panels.size(), M_PI);
    const Eigen::VectorXd theta_dot = RandomVector(rng, b.panels.size(), 2.0);
    const MassProperties m1 = ComputeMassProperties(b, theta, theta_dot);
    const MassProperties m2 = ComputeMassProperties(q, theta, theta_dot);
    const double scale = m1.J_B.norm();
    EXPECT_LT((Q * m1.J_B * Q.transpose() - m2.J_B).norm(), kRotatedRoundoffTolerance * scale);
    EXPECT_LT((Q * m1.Jdot_B * Q.transpose() - m2.Jdot_B).norm(),
              kRotatedRoundoffTolerance * scale);
    EXPECT_LT((Q * m1.h_rel_B - m2.h_rel_B).norm(), kRotatedRoundoffTolerance * scale);
    EXPECT_LT((Q * m1.com_B - m2.com_B).norm(), kRotatedRoundoffTolerance);
    EXPECT_DOUBLE_EQ(m1.mass, m2.mass);
  }
}

TEST(MassPropertiesTest, AtRestTheRatesVanishAndWithoutPanelsTheHubIsTheBody) {
  std::mt19937_64 rng(kSeed + 5);
  const HingedBody b = RandomBody(rng);
  const Eigen::VectorXd theta = RandomVector(rng, b.panels.size(), M_PI);
  const MassProperties mp = ComputeMassProperties(b, theta, Eigen::VectorXd::Zero(theta.size()));
  EXPECT_EQ(mp.Jdot_B, Mat3::Zero());
  EXPECT_EQ(mp.h_rel_B, Vec3::Zero());
  EXPECT_EQ(mp.com_rate_B, Vec3::Zero());
  EXPECT_NO_THROW(math::InertiaTensor::FromMatrix(mp.J_B));

  HingedBody hub_only;
  hub_only.hub = b.hub;
  const MassProperties h = ComputeMassProperties(hub_only, Eigen::VectorXd(), Eigen::VectorXd());
  EXPECT_EQ(h.mass, b.hub.body.mass);
  EXPECT_EQ(h.com_B, b.hub.com_B);
  EXPECT_LT((h.J_B - b.hub.body.inertia_cm).norm(), kRoundoffTolerance * h.J_B.norm());
}

#if DEPLOYSIM_COUNT_ALLOCATIONS
TEST(MassPropertiesTest, DoesNotAllocate) {
  std::mt19937_64 rng(kSeed + 6);
  const HingedBody b = RandomBody(rng);
  const Eigen::VectorXd theta = RandomVector(rng, b.panels.size(), M_PI);
  const Eigen::VectorXd theta_dot = RandomVector(rng, b.panels.size(), 2.0);
  const long before = g_allocations.load();
  MassProperties mp;
  for (int i = 0; i < 100; ++i) mp = ComputeMassProperties(b, theta, theta_dot);
  const long after = g_allocations.load();
  EXPECT_EQ(after - before, 0);
  EXPECT_GT(mp.mass, 0.0);
  // A tree, listed children first: panel 0 on panel 2 on panel 1 on the hub, panel 3 on
  // panel 1 (each panel's chain is walked, nothing stored).
  HingedBody tree = b;
  while (tree.panels.size() < 4) {
    tree.panels.push_back(tree.panels.front());
    tree.panels.back().name = "extra" + std::to_string(tree.panels.size());
  }
  tree.panels[0].parent = 2;
  tree.panels[1].parent = -1;
  tree.panels[2].parent = 1;
  tree.panels[3].parent = 1;
  tree = ValidatedHingedBody(tree, "tree");
  const Eigen::VectorXd t4 = RandomVector(rng, 4, M_PI);
  const Eigen::VectorXd r4 = RandomVector(rng, 4, 2.0);
  const long tree_before = g_allocations.load();
  for (int i = 0; i < 100; ++i) mp = ComputeMassProperties(tree, t4, r4);
  EXPECT_EQ(g_allocations.load() - tree_before, 0);
  EXPECT_NE(mp.h_rel_B, Vec3::Zero());
}
#endif  // DEPLOYSIM_COUNT_ALLOCATIONS

TEST(MassPropertiesTest, BoxInertiaValues) {
  // m/12 diag(y^2+z^2, x^2+z^2, x^2+y^2): 12 kg, 1 x 2 x 3 m -> diag(13, 10, 5).
  const Mat3 J = BoxInertia(12.0, Vec3(1.0, 2.0, 3.0));
  EXPECT_EQ(J, Vec3(13.0, 10.0, 5.0).asDiagonal().toDenseMatrix());
  // Cube: m a^2 / 6 about every axis.
  const Mat3 cube = BoxInertia(6.0, Vec3(0.5, 0.5, 0.5));
  EXPECT_DOUBLE_EQ(cube(0, 0), 0.25);
  EXPECT_DOUBLE_EQ(cube(1, 1), 0.25);
  EXPECT_DOUBLE_EQ(cube(2, 2), 0.25);
  // Thin plate: the normal moment is the sum of the in-plane ones (perpendicular axes).
  const Mat3 plate = BoxInertia(6.0, Vec3(0.8, 1.0, 0.0));
  EXPECT_DOUBLE_EQ(plate(2, 2), plate(0, 0) + plate(1, 1));
  EXPECT_DOUBLE_EQ(plate(0, 0), 0.5);
  EXPECT_THROW(BoxInertia(0.0, Vec3(1, 1, 1)), std::invalid_argument);
  EXPECT_THROW(BoxInertia(1.0, Vec3(1, -1, 1)), std::invalid_argument);
  EXPECT_THROW(BoxInertia(1.0, Vec3(1, std::nan(""), 1)), std::invalid_argument);
}

TEST(MassPropertiesTest, AxisAngleIsRodrigues) {
  const Mat3 Rz = AxisAngle(Vec3::UnitZ(), M_PI / 2);
  EXPECT_LT((Rz * Vec3::UnitX() - Vec3::UnitY()).norm(), 1e-15);
  std::mt19937_64 rng(kSeed + 7);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  for (int i = 0; i < 100; ++i) {
    const Vec3 axis = RandomOffAxisUnit(rng);
    const double angle = u(rng);
    const Mat3 R = AxisAngle(3.0 * axis, angle);  // the axis is normalized
    EXPECT_LT((R - math::ExpSO3(axis * angle)).norm(), 1e-14);
    EXPECT_LT((R * R.transpose() - Mat3::Identity()).norm(), 1e-14);
    EXPECT_LT((R * axis - axis).norm(), 1e-14);
  }
  EXPECT_THROW(AxisAngle(Vec3::Zero(), 1.0), std::invalid_argument);
}

// ---- invalid input ---------------------------------------------------------------

HingedBody TwoPanelBody() {
  HingedBody b;
  b.hub.body.mass = 80.0;
  b.hub.body.inertia_cm = BoxInertia(80.0, Vec3(0.6, 0.6, 0.8));
  for (int s : {1, -1}) {
    Panel p;
    p.name = s > 0 ? "wing_a" : "wing_b";
    p.body.mass = 6.0;
    p.body.inertia_cm = BoxInertia(6.0, Vec3(1.0, 0.02, 0.7));
    p.hinge_point_B = Vec3(0.3 * s, 0.0, 0.0);
    p.hinge_axis_B = Vec3(0.0, 2.0, 0.0);
    p.com_offset_B = Vec3(0.5 * s, 0.0, 0.0);
    b.panels.push_back(p);
  }
  return b;
}

/// Expects ValidatedHingedBody to reject `b`, with every string of `parts` in the message.
void ExpectRejected(const HingedBody& b, const std::vector<std::string>& parts) {
  try {
    ValidatedHingedBody(b, "models/test.yaml");
    ADD_FAILURE() << "accepted an invalid body; expected " << parts.back();
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("models/test.yaml"), std::string::npos) << msg;
    for (const std::string& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << msg;
  }
}

TEST(ValidatedHingedBodyTest, NormalizesTheHingeAxes) {
  const HingedBody b = ValidatedHingedBody(TwoPanelBody(), "models/test.yaml");
  EXPECT_EQ(b.panels[0].hinge_axis_B, Vec3::UnitY());
  EXPECT_EQ(b.panels[1].hinge_axis_B, Vec3::UnitY());
}

TEST(ValidatedHingedBodyTest, RejectsBadMasses) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  HingedBody b = TwoPanelBody();
  b.hub.body.mass = 0.0;
  ExpectRejected(b, {"hub.mass = 0", "rule: mass > 0"});
  b = TwoPanelBody();
  b.panels[1].body.mass = -2.5;
  ExpectRejected(b, {"panels[1] (wing_b).mass = -2.5", "rule: mass > 0"});
  b = TwoPanelBody();
  b.panels[0].body.mass = nan;
  ExpectRejected(b, {"panels[0] (wing_a).mass = nan", "rule: mass > 0"});
  b = TwoPanelBody();
  b.panels[0].body.mass = std::numeric_limits<double>::infinity();
  ExpectRejected(b, {"panels[0] (wing_a).mass = inf", "rule: mass > 0"});
}

TEST(ValidatedHingedBodyTest, RejectsBadInertias) {
  HingedBody b = TwoPanelBody();
  b.hub.body.inertia_cm(2, 2) = -1.0;
  ExpectRejected(b, {"hub.inertia", "rule: positive definite"});
  b = TwoPanelBody();
  b.panels[1].body.inertia_cm = Vec3(1.0, 1.0, 3.0).asDiagonal();
  ExpectRejected(b, {"panels[1] (wing_b).inertia", "rule: triangle inequality"});
  b = TwoPanelBody();
  b.panels[0].body.inertia_cm(0, 1) = 0.1;  // not symmetric
  ExpectRejected(b, {"panels[0] (wing_a).inertia", "rule: symmetric"});
  b = TwoPanelBody();
  b.panels[0].body.inertia_cm(0, 0) = std::numeric_limits<double>::quiet_NaN();
  ExpectRejected(b, {"panels[0] (wing_a).inertia", "rule: finite"});
}

TEST(ValidatedHingedBodyTest, RejectsBadVectors) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  HingedBody b = TwoPanelBody();
  b.panels[1].hinge_axis_B = Vec3::Zero();
  ExpectRejected(b, {"panels[1] (wing_b).hinge_axis = [0, 0, 0]", "rule: hinge axis non-zero"});
  b = TwoPanelBody();
  b.panels[0].hinge_axis_B = Vec3(0.0, nan, 1.0);
  ExpectRejected(b, {"panels[0] (wing_a).hinge_axis", "rule: finite"});
  b = TwoPanelBody();
  b.panels[0].hinge_point_B.x() = std::numeric_limits<double>::infinity();
  ExpectRejected(b, {"panels[0] (wing_a).hinge_point = [inf, 0, 0]", "rule: finite"});
  b = TwoPanelBody();
  b.panels[1].com_offset_B.z() = nan;
  ExpectRejected(b, {"panels[1] (wing_b).com_offset", "rule: finite"});
  b = TwoPanelBody();
  b.hub.com_B.y() = nan;
  ExpectRejected(b, {"hub.com", "rule: finite"});
}

// Unbounded, a hinge_point of 1e200 overflows J_B and shows up as the profile's "zero
// angular momentum": masses and positions are bounded so that J_B stays finite.
TEST(ValidatedHingedBodyTest, RejectsHugeMassesAndPositions) {
  HingedBody b = TwoPanelBody();
  b.panels[0].hinge_point_B.x() = 1e200;
  ExpectRejected(b, {"panels[0] (wing_a).hinge_point", "rule: |component| <= 1e+06 m"});
  b = TwoPanelBody();
  b.panels[1].com_offset_B.y() = -2e6;
  ExpectRejected(b, {"panels[1] (wing_b).com_offset", "rule: |component| <= 1e+06 m"});
  b = TwoPanelBody();
  b.hub.com_B.z() = 1e7;
  ExpectRejected(b, {"hub.com", "rule: |component| <= 1e+06 m"});
  b = TwoPanelBody();
  b.hub.body.mass = 1e13;
  ExpectRejected(b, {"hub.mass = ", "too large (rule: mass <= 1e+12 kg)"});
  // At the bounds: J_B finite.
  b = TwoPanelBody();
  b.hub.body.mass = kMaxPartMass;
  b.panels[0].hinge_point_B.x() = kMaxCoordinate;
  const HingedBody ok = ValidatedHingedBody(b, "models/test.yaml");
  const MassProperties mp =
      ComputeMassProperties(ok, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2));
  EXPECT_TRUE(mp.J_B.allFinite());
}

/// TwoPanelBody with panels seg_a, seg_b, ... appended (each on the hub).
HingedBody BodyWithSegments(int segments) {
  HingedBody b = TwoPanelBody();
  for (int i = 0; i < segments; ++i) {
    Panel p = b.panels[0];
    p.name = std::string("seg_") + static_cast<char>('a' + i);
    b.panels.push_back(p);
  }
  return b;
}

TEST(ValidatedHingedBodyTest, AcceptsTreesInAnyOrder) {
  HingedBody b = BodyWithSegments(3);  // wing_a, wing_b, seg_a, seg_b, seg_c
  b.panels[0].parent = 4;              // wing_a on seg_c, listed before it
  b.panels[4].parent = 1;              // seg_c on wing_b
  b.panels[3].parent = 1;              // seg_b on wing_b too: a branch
  const HingedBody v = ValidatedHingedBody(b, "models/test.yaml");
  EXPECT_EQ(v.panels[0].parent, 4);
  EXPECT_EQ(v.panels[4].parent, 1);
  EXPECT_EQ(v.panels[2].parent, -1);
}

TEST(ValidatedHingedBodyTest, RejectsParentsOutOfRangeAndItself) {
  HingedBody b = TwoPanelBody();
  b.panels[1].parent = 2;
  ExpectRejected(b, {"panels[1] (wing_b).parent = 2: no such panel",
                     "(rule: parent is -1 for the hub or the index of another panel, 0 to 1)"});
  b.panels[1].parent = -2;
  ExpectRejected(b, {"panels[1] (wing_b).parent = -2: no such panel"});
  b.panels[1].parent = 1;
  ExpectRejected(b, {"panels[1] (wing_b).parent = wing_b: a panel cannot be its own parent",
                     "(rule: panels form a tree)"});
}

TEST(ValidatedHingedBodyTest, RejectsCycles) {
  // The message of the issue: seg_b and seg_c hang on each other.
  HingedBody b = BodyWithSegments(3);  // panels[2..4] = seg_a, seg_b, seg_c
  b.panels[3].parent = 4;
  b.panels[4].parent = 3;
  b.panels[2].parent = 3;  // seg_a hangs on the cycle without being on it
  try {
    ValidatedHingedBody(b, "models/x.yaml");
    ADD_FAILURE() << "accepted a cycle";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "models/x.yaml: panels[3] (seg_b).parent = seg_c: the panels' parents form a "
              "cycle (seg_b -> seg_c -> seg_b) (rule: panels form a tree)");
  }
  // A longer cycle is shown from its panel of lowest index; unnamed panels by index.
  b = BodyWithSegments(3);
  b.panels[0].parent = 4;  // wing_a -> seg_c -> wing_b -> wing_a
  b.panels[4].parent = 1;
  b.panels[1].parent = 0;
  b.panels[1].name.clear();
  ExpectRejected(b, {"panels[0] (wing_a).parent = seg_c: the panels' parents form a cycle "
                     "(wing_a -> seg_c -> panels[1] -> wing_a) (rule: panels form a tree)"});
}

TEST(ValidatedHingedBodyTest, LimitsTheDepthOfTheTree) {
  // A chain of kMaxPanelDepth panels is accepted, one more is not.
  HingedBody b = TwoPanelBody();
  b.panels.resize(1);
  for (int k = 1; k < kMaxPanelDepth; ++k) {
    Panel p = b.panels[0];
    p.name = "link" + std::to_string(k);
    p.parent = k - 1;
    b.panels.push_back(p);
  }
  const HingedBody ok = ValidatedHingedBody(b, "models/test.yaml");
  const auto n = static_cast<Eigen::Index>(ok.panels.size());
  const MassProperties mp =
      ComputeMassProperties(ok, Eigen::VectorXd::Constant(n, 0.1), Eigen::VectorXd::Ones(n));
  EXPECT_TRUE(mp.J_B.allFinite());
  Panel last = b.panels.back();
  last.name = "one_too_many";
  last.parent = kMaxPanelDepth - 1;
  b.panels.push_back(last);
  const std::string n_max = std::to_string(kMaxPanelDepth);
  ExpectRejected(
      b, {"panels[" + n_max + "] (one_too_many).parent = link" +
              std::to_string(kMaxPanelDepth - 1) + ": the chain from the hub to one_too_many has " +
              std::to_string(kMaxPanelDepth + 1) + " panels",
          "(rule: a chain of panels from the hub has at most " + n_max + ")"});
}

TEST(MassPropertiesTest, RejectsBodiesThatAreNotTrees) {
  // Not validated: a cycle must not loop for ever, nor an index read out of range.
  HingedBody b = ValidatedHingedBody(TwoPanelBody(), "models/test.yaml");
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(2);
  b.panels[0].parent = 1;
  b.panels[1].parent = 0;
  EXPECT_THROW(ComputeMassProperties(b, zero, zero), std::invalid_argument);
  b.panels[1].parent = 7;
  EXPECT_THROW(ComputeMassProperties(b, zero, zero), std::invalid_argument);
}

TEST(ValidatedHingedBodyTest, RejectsDuplicatePanelNames) {
  HingedBody b = TwoPanelBody();
  b.panels[1].name = "wing_a";
  ExpectRejected(b, {"panels[1] (wing_a)", "rule: unique panel names"});
}

TEST(MassPropertiesTest, RejectsMismatchedSizesAndUnnormalizedAxes) {
  const HingedBody b = ValidatedHingedBody(TwoPanelBody(), "models/test.yaml");
  EXPECT_THROW(ComputeMassProperties(b, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(2)),
               std::invalid_argument);
  EXPECT_THROW(ComputeMassProperties(b, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(3)),
               std::invalid_argument);
  Eigen::VectorXd bad = Eigen::VectorXd::Zero(2);
  bad[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(ComputeMassProperties(b, bad, Eigen::VectorXd::Zero(2)), std::invalid_argument);
  try {
    ComputeMassProperties(TwoPanelBody(), Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2));
    ADD_FAILURE() << "accepted a non-unit hinge axis";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not a unit vector"), std::string::npos) << e.what();
  }
}

TEST(ModelTest, ConfigurationLookupNamesTheValidOnes) {
  Model m;
  m.name = "seed_satellite";
  m.source = "models/seed_satellite.yaml";
  m.configurations.push_back({"closed", Mat3::Identity(), Eigen::VectorXd()});
  m.configurations.push_back({"open", 2.0 * Mat3::Identity(), Eigen::VectorXd()});
  EXPECT_EQ(m.configuration("open").J_B(0, 0), 2.0);
  try {
    m.configuration("half_open");
    ADD_FAILURE() << "found a configuration that does not exist";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("models/seed_satellite.yaml"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'half_open'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("closed, open"), std::string::npos) << msg;
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::model
