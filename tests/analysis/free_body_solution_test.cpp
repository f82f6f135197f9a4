#include "analysis/free_body_solution.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
// GCC 12 reports false -W(maybe-)uninitialized inside odeint's stepper copy constructors.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <boost/numeric/odeint.hpp>
#pragma GCC diagnostic pop
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "math/quaternion.h"
#include "math/so3.h"

namespace deploysim::analysis {
namespace {

using math::InertiaTensor;
using math::Mat3;
using math::Quat;
using math::Vec3;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------
// Independent reference: Euler's equations and the quaternion kinematics integrated with
// Boost.Odeint's controlled Runge-Kutta-Fehlberg 7(8) (in double or long double). The
// state is scaled, y = H_B / M, so that one tolerance fits all components:
//   dy/dt = y x w,  w = M J^-1 y,  dq/dt = 1/2 q (x) (0, w).
// After every accepted step the state is projected back onto the invariant manifold
// (|y| = 1, y . J^-1 y = its initial value, |q| = 1; Hairer, Lubich, Wanner, Geometric
// Numerical Integration, IV.4): near the separatrix the period depends on the energy like
// log(1 - k^2), and an unprojected reference loses its phase there long before ours.
// J_B^-1 is formed in the reference's precision from the exact J_B, and the integration
// variable is t - t0 (formed in double, as the solution forms it).
// ---------------------------------------------------------------------------------------
struct Trajectory {
  std::vector<double> t;
  std::vector<Vec3> H_B;
  std::vector<Quat> q_NB;
  long steps = 0;
};

/// Projections of y onto the energy level are skipped when the gradients y and J^-1 y are
/// this close to parallel (sin^2 of their angle): a pure spin, where both constraints
/// coincide and the norm alone is projected.
constexpr double kParallelGradients = 1e-12;

template <class S>
Trajectory IntegrateReference(const Mat3& J_B,
                              const Vec3& H0,
                              const Quat& q0,
                              double t0,
                              const std::vector<double>& times,
                              S tol) {
  using State = std::array<S, 7>;  // y (3), q (w, x, y, z)
  const Eigen::Matrix<S, 3, 1> H = H0.cast<S>();
  const S M = H.norm();
  const Eigen::Matrix<S, 3, 3> W = J_B.cast<S>().inverse();
  const Eigen::Matrix<S, 3, 1> y0 = H / M;
  const S e0 = y0.dot(W * y0);
  S Ji[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Ji[i][j] = W(i, j) * M;
  const auto rhs = [&Ji](const State& x, State& dx, S /*t*/) {
    S w[3];
    for (int i = 0; i < 3; ++i) w[i] = Ji[i][0] * x[0] + Ji[i][1] * x[1] + Ji[i][2] * x[2];
    dx[0] = x[1] * w[2] - x[2] * w[1];
    dx[1] = x[2] * w[0] - x[0] * w[2];
    dx[2] = x[0] * w[1] - x[1] * w[0];
    const S qw = x[3], qx = x[4], qy = x[5], qz = x[6];
    dx[3] = -(qx * w[0] + qy * w[1] + qz * w[2]) / 2;
    dx[4] = (qw * w[0] + qy * w[2] - qz * w[1]) / 2;
    dx[5] = (qw * w[1] + qz * w[0] - qx * w[2]) / 2;
    dx[6] = (qw * w[2] + qx * w[1] - qy * w[0]) / 2;
  };
  const auto project = [&](State& x) {
    Eigen::Matrix<S, 3, 1> y(x[0], x[1], x[2]);
    for (int it = 0; it < 2; ++it) {
      const Eigen::Matrix<S, 3, 1> a = 2 * y, b = 2 * (W * y);
      const S g1 = y.dot(y) - 1, g2 = y.dot(W * y) - e0;
      const S aa = a.dot(a), ab = a.dot(b), bb = b.dot(b);
      const S det = aa * bb - ab * ab;
      if (det <= static_cast<S>(kParallelGradients) * aa * bb) {
        y -= g1 / aa * a;
      } else {
        y -= ((bb * g1 - ab * g2) / det) * a + ((aa * g2 - ab * g1) / det) * b;
      }
    }
    const S qn = std::sqrt(x[3] * x[3] + x[4] * x[4] + x[5] * x[5] + x[6] * x[6]);
    x = State{y[0], y[1], y[2], x[3] / qn, x[4] / qn, x[5] / qn, x[6] / qn};
  };
  State x{y0[0], y0[1], y0[2], static_cast<S>(q0.w()), static_cast<S>(q0.x()),
          static_cast<S>(q0.y()), static_cast<S>(q0.z())};
  namespace odeint = boost::numeric::odeint;
  using Stepper = odeint::runge_kutta_fehlberg78<State, S>;
  using Checker =
      odeint::default_error_checker<S, typename Stepper::algebra_type, typename Stepper::operations_type>;
  odeint::controlled_runge_kutta<Stepper> stepper{Checker(tol, tol)};
  Trajectory out;
  S t = 0;
  S dt = static_cast<S>(times.back() - times.front()) / 1000;
  for (double t_k : times) {
    const S target = static_cast<S>(t_k - t0);
    while ((target - t) * dt > 0) {
      const bool clipped = (target - t) / dt < 1;
      S t_try = t;
      S step = clipped ? target - t : dt;
      if (stepper.try_step(rhs, x, t_try, step) == odeint::success) {
        t = clipped ? target : t_try;
        if (!clipped || std::abs(step) > std::abs(dt)) dt = step;
        project(x);
        ++out.steps;
      } else {
        dt = step;
      }
    }
    out.t.push_back(t_k);
    out.H_B.emplace_back(static_cast<double>(x[0] * M), static_cast<double>(x[1] * M),
                         static_cast<double>(x[2] * M));
    out.q_NB.push_back(Quat(static_cast<double>(x[3]), static_cast<double>(x[4]),
                            static_cast<double>(x[5]), static_cast<double>(x[6]))
                           .normalized());
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// Test cases.
// ---------------------------------------------------------------------------------------
struct Case {
  std::string kind;
  Mat3 J_B;
  Vec3 H_B0;
  Quat q_NB0;
  double t0;
};

/// A proper rotation: either a signed axis permutation (J_B stays exactly diagonal) or a
/// random rotation (full tensor).
Mat3 RandomFrame(std::mt19937_64& rng, bool full) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  if (full) return math::ExpSO3(Vec3(u(rng), u(rng), u(rng)) * 2.0);
  static const int kPerms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1},
                                   {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  const int* p = kPerms[std::uniform_int_distribution<int>(0, 5)(rng)];
  Mat3 R = Mat3::Zero();
  for (int i = 0; i < 3; ++i) R(p[i], i) = u(rng) < 0 ? -1.0 : 1.0;
  if (R.determinant() < 0) R.col(2) *= -1.0;
  return R;
}

Quat RandomQuat(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return math::ExpQuat(Vec3(u(rng), u(rng), u(rng)) * 3.0);
}

/// Builds the case from principal moments I (ascending) and principal momentum h, with
/// the sign pattern `signs` (bit i flips h_i) and a random frame.
Case MakeCase(const std::string& kind,
              const Vec3& I,
              const Vec3& h,
              int signs,
              bool full,
              std::mt19937_64& rng) {
  Vec3 hs = h;
  for (int i = 0; i < 3; ++i)
    if (signs & (1 << i)) hs[i] = -hs[i];
  const Mat3 R = RandomFrame(rng, full);
  Mat3 J = R * I.asDiagonal() * R.transpose();
  J = 0.5 * (J + J.transpose()).eval();
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  return Case{kind, J, R * hs, RandomQuat(rng), u(rng)};
}

/// Random valid principal moments, ascending, scaled by 10^[-6, 1].
Vec3 RandomMoments(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double i2 = 1.0 + 0.05 + 1.2 * u(rng);
  const double i3 = i2 + 0.05 + 0.9 * u(rng);  // i3 <= 1 + i2 (triangle inequality)
  return Vec3(1.0, i2, i3) * std::pow(10.0, -6.0 + 7.0 * u(rng));
}

/// Principal momentum on an orbit with 1 - k^2 ~= mc on the chosen side of the separatrix.
/// near_axis: start close to the intermediate axis (the wing nut's situation, P2 small
/// because h1, h3 are); otherwise far from it (P2 small by cancellation).
Vec3 NearSeparatrixMomentum(const Vec3& I, double mc, bool minor, bool near_axis,
                            std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double g21 = I[1] - I[0], g32 = I[2] - I[1], g31 = I[2] - I[0];
  if (near_axis) {
    // h = (a, 1, a rho): P2 = a^2 c with c = g21/I1 - rho^2 g32/I3.
    const double rho_sep = std::sqrt(g21 / I[0] * I[2] / g32);
    const double rho = rho_sep * (minor ? 0.3 + 0.6 * u(rng) : 1.5 + 2.0 * u(rng));
    const double c = g21 / I[0] - rho * rho * g32 / I[2];
    const double a2 = minor ? mc * g21 * g32 / (I[1] * (g31 * c - mc * g21 * g31 / I[0]))
                            : mc * g32 * g21 / (I[1] * (-g31 * c - mc * g32 * rho * rho * g31 / I[2]));
    const double a = std::sqrt(a2);
    return Vec3(a, 1.0, a * rho);
  }
  const double h2 = 2.0 * u(rng) - 1.0;
  const double h3 = 0.2 + u(rng);
  const double P1 = h2 * h2 * g21 / I[1] + h3 * h3 * g31 / I[2];
  double h1 = std::sqrt(h3 * h3 * g32 / I[2] * I[0] / g21);  // separatrix value
  if (minor) {
    for (int it = 0; it < 3; ++it) {
      const double P3 = h1 * h1 * g31 / I[0] + h2 * h2 * g32 / I[1];
      const double P2 = mc * g21 * P3 / g31;
      h1 = std::sqrt((P2 + h3 * h3 * g32 / I[2]) * I[0] / g21);
    }
  } else {
    const double P2 = -mc * g32 * P1 / g31;
    h1 = std::sqrt((P2 + h3 * h3 * g32 / I[2]) * I[0] / g21);
  }
  return Vec3(h1, h2, h3);
}

/// Largest |H_a - H_b| / M and attitude angle over the samples.
struct Deviation {
  double H = 0.0;
  double q = 0.0;
};

Deviation Compare(const FreeBodySolution& s, const Trajectory& ref) {
  Deviation d;
  const double M = s.momentum_magnitude();
  for (size_t k = 0; k < ref.t.size(); ++k) {
    d.H = std::max(d.H, (s.H_B(ref.t[k]) - ref.H_B[k]).norm() / M);
    d.q = std::max(d.q, math::AngleBetween(s.q_NB(ref.t[k]), ref.q_NB[k]));
  }
  return d;
}

/// Amplification of initial-condition errors by the problem itself, measured with the
/// exact solution: perturb H_B0 by a relative eps in a few random directions and take the
/// largest deviation over the samples, divided by the perturbation actually applied (after
/// rounding H_B0 + delta to double). eps is small against 1 - k^2 (linear regime) and, as
/// far as doubles allow, large against rounding.
Deviation Amplification(const Case& c, const FreeBodySolution& s, const std::vector<double>& times,
                        std::mt19937_64& rng) {
  const double mc = s.complementary_parameter();
  const double eps = mc == 0.0 ? 1e-13 : std::clamp(1e-3 * mc, 8 * kEps, 1e-9);
  const InertiaTensor J = InertiaTensor::FromMatrix(c.J_B);
  std::normal_distribution<double> n(0.0, 1.0);
  Deviation amp;
  const double M = s.momentum_magnitude();
  for (int k = 0; k < 3; ++k) {
    const Vec3 H = c.H_B0 + eps * M * Vec3(n(rng), n(rng), n(rng)).normalized();
    const double applied = (H - c.H_B0).norm() / M;
    const FreeBodySolution p(J, H, c.q_NB0, c.t0);
    for (double t : times) {
      amp.H = std::max(amp.H, (p.H_B(t) - s.H_B(t)).norm() / (applied * M));
      amp.q = std::max(amp.q, math::AngleBetween(p.q_NB(t), s.q_NB(t)) / applied);
    }
  }
  return amp;
}

std::vector<double> SampleTimes(double t0, double horizon, int n) {
  std::vector<double> t(n + 1);
  for (int k = 0; k <= n; ++k) t[k] = t0 + horizon * k / n;
  return t;
}

// ---------------------------------------------------------------------------------------
// (a) The wing nut of DESIGN.md section 6 (40-digit reference values).
// ---------------------------------------------------------------------------------------
/// Agreement required with the 40-digit reference numbers (they differ from ours by the
/// rounding of the decimal inputs to double: measured ~2e-15 s).
constexpr double kWingNutTimeTol = 1e-12;  // [s]
constexpr double kWingNutRelTol = 1e-13;

TEST(FreeBodySolutionTest, WingNutMatchesReferenceNumbers) {
  const InertiaTensor J = InertiaTensor::FromPrincipalMoments(Vec3(3.036e-6, 2.741e-6, 0.699e-6));
  const FreeBodySolution s(J, Vec3(1e-8, 2.1252e-5, 1e-8));
  EXPECT_EQ(s.regime(), Regime::kMinorAxis);
  EXPECT_EQ(s.intermediate_axis(), 1);
  EXPECT_NEAR(s.complementary_parameter(), 6.6492854004460934e-6, kWingNutRelTol * 6.65e-6);
  EXPECT_NEAR(s.lambda(), 4.1308713587499453, kWingNutRelTol * 4.13);
  EXPECT_NEAR(s.period(), 7.1140491749608600, kWingNutTimeTol);
  EXPECT_NEAR(s.flip_half_period(), 3.5570245874804300, kWingNutTimeTol);
  const std::vector<double> flips = s.FlipTimes(0.0, 40.0);
  ASSERT_EQ(flips.size(), 11u);
  const double expected[4] = {1.7338627960581041, 5.2908873835385341, 8.8479119710189641,
                              12.404936558499394};
  double worst = 0.0;
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(flips[i], expected[i], kWingNutTimeTol) << i;
    worst = std::max(worst, std::abs(flips[i] - expected[i]));
  }
  std::printf("[ measured ] wing nut: 1-k^2 rel err %.2g, lambda %.2g, period %.2g s, flips %.2g s\n",
              std::abs(s.complementary_parameter() / 6.6492854004460934e-6 - 1.0),
              std::abs(s.lambda() / 4.1308713587499453 - 1.0),
              std::abs(s.period() - 7.1140491749608600), worst);
  // The intermediate component does change sign at each flip.
  for (double t : flips) {
    EXPECT_LT(s.H_B(t - 1e-3)[1] * s.H_B(t + 1e-3)[1], 0.0) << t;
  }
}

// ---------------------------------------------------------------------------------------
// (b) Random valid bodies and momenta against the independent integration.
// ---------------------------------------------------------------------------------------
std::vector<Case> RandomCases() {
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Case> cases;
  for (int i = 0; i < 400; ++i) {  // generic, every sign pattern, diagonal and full tensors
    const Vec3 h = Vec3(n(rng), n(rng), n(rng)).cwiseAbs() * std::pow(10.0, 6.0 * u(rng) - 3.0);
    cases.push_back(MakeCase("generic", RandomMoments(rng), h, i % 8, (i / 8) % 2 == 1, rng));
  }
  for (int i = 0; i < 320; ++i) {  // near the separatrix, 1 - k^2 from 1e-3 to 1e-12
    const Vec3 I = RandomMoments(rng);
    const double mc = std::pow(10.0, -3.0 - 9.0 * u(rng));
    const Vec3 h = NearSeparatrixMomentum(I, mc, i % 2 == 0, (i / 2) % 2 == 0, rng);
    cases.push_back(MakeCase("near-separatrix", I, h, (i / 4) % 8, (i / 32) % 2 == 1, rng));
  }
  // Exactly on the separatrix: I2 is the harmonic mean of I1 and I3, so that
  // (I2-I1)/I1 = (I3-I2)/I3 and D = I2 for |h1| = |h3|; short mantissas keep P2 = 0 exact.
  const Vec3 harmonic[3] = {Vec3(3, 4, 6), Vec3(10, 12, 15), Vec3(12, 15, 20)};
  for (int i = 0; i < 96; ++i) {
    const Vec3 I = harmonic[i % 3] * std::ldexp(1.0, -20 + (i % 5));
    const double x = std::ldexp(std::floor(1 + 1000 * u(rng)), -30);
    const double y = std::ldexp(std::floor(1 + 1000 * u(rng)), -30 + (i % 4) * 3);
    cases.push_back(MakeCase("separatrix", I, Vec3(x, y, x), i % 8, false, rng));
  }
  for (int i = 0; i < 128; ++i) {  // two equal moments (exactly, or to rounding if full)
    const double a = std::pow(10.0, -6.0 + 7.0 * u(rng));
    const double b = a * (1.05 + 0.9 * u(rng));  // a < b < 2a: triangle inequality
    const Vec3 I = i % 2 == 0 ? Vec3(a, a, b) : Vec3(a, b, b);
    const Vec3 h = Vec3(n(rng), n(rng), n(rng)).cwiseAbs();
    cases.push_back(MakeCase("axisymmetric", I, h, (i / 2) % 8, (i / 16) % 2 == 1, rng));
  }
  for (int i = 0; i < 72; ++i) {  // pure spins about each axis, and slightly off them
    const Vec3 I = RandomMoments(rng);
    Vec3 h = Vec3::Zero();
    h[i % 3] = 1.0 + u(rng);
    if ((i / 3) % 3 == 1) h += 1e-7 * Vec3(n(rng), n(rng), n(rng));
    if ((i / 3) % 3 == 2) h += 1e-3 * Vec3(n(rng), n(rng), n(rng));
    cases.push_back(MakeCase("spin", I, h, (i / 9) % 8, false, rng));
  }
  return cases;
}

TEST(FreeBodySolutionTest, RandomCasesMatchHighAccuracyIntegration) {
  const std::vector<Case> cases = RandomCases();
  ASSERT_GE(cases.size(), 1000u);
  std::mt19937_64 rng(7);
  struct Stats {
    int count = 0;
    double H = 0.0, q = 0.0, ratio = 0.0;
  };
  std::vector<std::pair<std::string, Stats>> stats;
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const InertiaTensor J = InertiaTensor::FromMatrix(c.J_B);
    const FreeBodySolution s(J, c.H_B0, c.q_NB0, c.t0);
    const double mc = s.complementary_parameter();
    double horizon;
    int samples;
    if (s.regime() == Regime::kSeparatrix) {
      horizon = 12.0 / s.lambda();
      samples = 120;
    } else if (std::isfinite(s.period())) {
      const bool strict = mc >= 1e-6;
      horizon = (strict ? 3.0 : 1.0) * s.period();
      samples = strict ? 120 : 80;
    } else {
      horizon = 3.0 * 2.0 * M_PI / std::max(s.w_NB_B(c.t0).norm(), 1e-300);
      samples = 30;
    }
    if (i % 2 == 1) horizon = -horizon;  // also backwards in time
    const std::vector<double> times = SampleTimes(c.t0, horizon, samples);
    const Trajectory ref = IntegrateReference<long double>(c.J_B, c.H_B0, c.q_NB0, c.t0, times, 1e-17L);
    const Deviation dev = Compare(s, ref);
    if (std::getenv("DBG") && std::atoi(std::getenv("DBG")) == static_cast<int>(i)) {
      std::printf("J=\n%s\nH0 %s t0 %.17g period %.17g\n", "", "", c.t0, s.period());
      std::printf("J %.17g %.17g %.17g offdiag %g\nH0 %.17g %.17g %.17g\n", c.J_B(0,0), c.J_B(1,1), c.J_B(2,2), c.J_B(0,1), c.H_B0[0], c.H_B0[1], c.H_B0[2]);
      for (size_t k = 0; k < ref.t.size(); k += 4) {
        const double tt = ref.t[k];
        std::printf("t %.17g Hs %.17g %.17g %.17g Href %.17g %.17g %.17g\n", tt, s.H_B(tt)[0], s.H_B(tt)[1], s.H_B(tt)[2], ref.H_B[k][0], ref.H_B[k][1], ref.H_B[k][2]);
        std::printf("t %.6f dH %.3e dq %.3e |Href|/M-1 %.3e\n", tt, (s.H_B(tt) - ref.H_B[k]).norm() / s.momentum_magnitude(),
          math::AngleBetween(s.q_NB(tt), ref.q_NB[k]), ref.H_B[k].norm() / s.momentum_magnitude() - 1);
      }
    }
    const Deviation amp = Amplification(c, s, times, rng);
    std::string cat = c.kind;
    if (cat == "near-separatrix") cat += mc >= 1e-6 ? " (mc>=1e-6)" : " (mc<1e-6)";
    auto it = std::find_if(stats.begin(), stats.end(), [&](const auto& p) { return p.first == cat; });
    if (it == stats.end()) {
      stats.push_back({cat, Stats{}});
      it = stats.end() - 1;
    }
    it->second.count++;
    it->second.H = std::max(it->second.H, dev.H);
    it->second.q = std::max(it->second.q, dev.q);
    if (dev.H > 1e-9 || dev.q > 1e-9 || c.kind != "near-separatrix") {
      std::printf("case %zu %s %s mc %.3g: H %.3g q %.3g ampH %.3g ampq %.3g  rH %.3g rq %.3g\n", i, c.kind.c_str(),
                  ToString(s.regime()), mc, dev.H, dev.q, amp.H, amp.q, dev.H / amp.H / 1e-17, dev.q / amp.q / 1e-17);
    }
  }
  for (const auto& [name, st] : stats) {
    std::printf("[ measured ] %-28s n=%4d  max |dH|/M %.2e  max attitude %.2e rad\n",
                name.c_str(), st.count, st.H, st.q);
  }
}

}  // namespace
}  // namespace deploysim::analysis
