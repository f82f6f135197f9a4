// Classic test problems with closed-form solutions (issue acceptance 5):
//  (a) Krogh's rigid-body problem (MATLAB `rigidode`), run through the rigid-body
//      steppers, against Jacobi's elliptic functions;
//  (b) the seed's appendix B damped oscillator, run through the generic Runge-Kutta
//      loop that the rigid-body steppers use (rk_engine.h), against its closed form.

#include <gtest/gtest.h>

#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/integrators/butcher_tableau.h"
#include "deploysim/integrators/factory.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/integrators/rk_engine.h"
#include "deploysim/math/inertia.h"

namespace deploysim::integrators {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

std::string Fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.4g", x);
  return buf;
}

// ---------------------------------------------------------------------------------
// (a) Krogh's rigidode: y1' = y2 y3, y2' = -y1 y3, y3' = -0.51 y1 y2, y(0) = (0, 1, 1),
// exact y = (sn, cn, dn)(t | m = 0.51) (F. T. Krogh, JPL, 1973; Shampine & Reichelt,
// "The MATLAB ODE suite", SIAM J. Sci. Comput. 18 (1997)). As a free rigid body:
// J = diag(1, 2, 3) kg m^2, H_B(0) = (sqrt(3), 0, sqrt(4.59)); then
// H_B(t) = (sqrt(3) dn, sqrt(6.12) sn, sqrt(4.59) cn), because Euler's equations
// H' = H x J^-1 H read H1' = -H2 H3 / 6, H2' = 2/3 H3 H1, H3' = -H1 H2 / 2, and with
// H = (a dn, b sn, c cn) they become sn' = cn dn, cn' = -sn dn, dn' = -m sn cn when
// b = 2ac/3, c = ab/2 and m = bc/(6a): a^2 = 3, b^2 = 4c^2/3 = 6.12, m = c^2/9 = 0.51.
// KroghMappingSolvesEulerEquations checks this numerically.

constexpr double kKroghM = 0.51;                // parameter m = k^2
constexpr double kKroghHorizon = 12.0;          // [s], MATLAB rigidode's tspan
constexpr double kKroghGridSpacing = 0.25;      // [s]
const math::Vec3 kKroghMoments(1.0, 2.0, 3.0);  // [kg m^2]
const math::Vec3 kKroghScale(std::sqrt(3.0), std::sqrt(6.12), std::sqrt(4.59));  // [kg m^2/s]

/// (sn, cn, dn)(t | m) from Boost (Landau-Gauss AGM; accurate to a few ulps at m=0.51).
math::Vec3 SnCnDn(double t) {
  double cn = 0.0;
  double dn = 0.0;
  const double sn = boost::math::jacobi_elliptic(std::sqrt(kKroghM), t, &cn, &dn);
  return math::Vec3(sn, cn, dn);
}

/// The exact H_B(t) of the body above.
math::Vec3 KroghMomentum(double t) {
  const math::Vec3 y = SnCnDn(t);
  return math::Vec3(kKroghScale[0] * y[2], kKroghScale[1] * y[0], kKroghScale[2] * y[1]);
}

/// Max over the grid of the error in the (sn, cn, dn) scale: |H_i - H_i,exact| / scale_i.
double KroghError(const std::vector<State>& samples) {
  double worst = 0.0;
  for (const State& s : samples) {
    const math::Vec3 d = (s.H_B - KroghMomentum(s.t)).cwiseQuotient(kKroghScale);
    worst = std::max(worst, d.cwiseAbs().maxCoeff());
  }
  return worst;
}

double RunKrogh(const std::string& method, const IntegratorSettings& settings) {
  const dynamics::ConstantInertia source(
      math::InertiaTensor::FromPrincipalMoments(kKroghMoments, "rigidode"));
  const std::vector<double> grid = UniformGrid(0.0, kKroghHorizon, kKroghGridSpacing);
  const std::unique_ptr<Stepper> stepper = MakeNumericalStepper(method);
  const IntegrationResult r =
      Integrate(*stepper, settings, source, State{0.0, KroghMomentum(0.0), math::Quat::Identity()},
                kKroghHorizon, grid);
  EXPECT_EQ(r.termination, Termination::kReachedEnd) << method << ": " << r.message;
  EXPECT_EQ(r.samples.size(), grid.size()) << method;
  return KroghError(r.samples);
}

TEST(ClassicProblemsTest, KroghMappingSolvesEulerEquations) {
  // The oracle itself: the initial momentum is the stated one, and the mapped
  // (sn, cn, dn) satisfies H' = H x J^-1 H, with H' from sn' = cn dn, cn' = -sn dn,
  // dn' = -m sn cn. Also rigidode's own equations for y = (sn, cn, dn).
  constexpr double kOracleTolerance = 1e-14;  // a few ulps of O(1) quantities
  const math::Vec3 H0 = KroghMomentum(0.0);
  EXPECT_NEAR(H0[0], std::sqrt(3.0), kOracleTolerance);
  EXPECT_NEAR(H0[1], 0.0, kOracleTolerance);
  EXPECT_NEAR(H0[2], std::sqrt(4.59), kOracleTolerance);
  EXPECT_NEAR(kKroghScale[1] * kKroghScale[2] / (6.0 * kKroghScale[0]), kKroghM, kOracleTolerance);
  const dynamics::InertiaSample s =
      dynamics::ConstantInertia(math::InertiaTensor::FromPrincipalMoments(kKroghMoments))
          .Evaluate(0.0);
  for (double t = 0.0; t <= kKroghHorizon; t += 0.37) {
    const math::Vec3 y = SnCnDn(t);  // (sn, cn, dn)
    // rigidode's right-hand side at y.
    const math::Vec3 y_dot(y[1] * y[2], -y[0] * y[2], -0.51 * y[0] * y[1]);
    // Boost's (sn, cn, dn) solves rigidode: central differences of its values.
    constexpr double kDiffStep = 1e-5;
    // Truncation kDiffStep^2 / 6 |y'''| <= 2e-11, plus rounding ~1e-16 / kDiffStep.
    constexpr double kDiffTolerance = 3e-10;  // measured 6.3e-11
    const math::Vec3 fd = (SnCnDn(t + kDiffStep) - SnCnDn(t - kDiffStep)) / (2.0 * kDiffStep);
    EXPECT_LT((fd - y_dot).cwiseAbs().maxCoeff(), kDiffTolerance) << "t = " << t;
    // The mapped momentum solves Euler's equations, H' = H x J^-1 H.
    const math::Vec3 H = KroghMomentum(t);
    const math::Vec3 H_dot(kKroghScale[0] * y_dot[2], kKroghScale[1] * y_dot[0],
                           kKroghScale[2] * y_dot[1]);
    const math::Vec3 rhs = dynamics::MomentumRate(H, dynamics::AngularVelocity(s, H));
    EXPECT_LT((H_dot - rhs).cwiseAbs().maxCoeff(), kOracleTolerance) << "t = " << t;
  }
}

TEST(ClassicProblemsTest, KroghAdaptiveMethodsMatchJacobiFunctions) {
  constexpr double kAdaptiveTolerance = 1e-12;  // in the sn/cn/dn scale
  IntegratorSettings s;
  s.tolerances = {1e-14, 1e-16};
  for (const char* method : {"rkf78", "rkmk-rkf78"}) {
    const double e = RunKrogh(method, s);
    ::testing::Test::RecordProperty(std::string("krogh_") + method + "_error", Fmt(e));
    EXPECT_LE(e, kAdaptiveTolerance) << method;
  }
}

TEST(ClassicProblemsTest, KroghFixedStepMethodsAreFourthOrder) {
  constexpr double kOrderTolerance = 0.2;  // as in convergence_test.cpp
  // Coarsest steps [s]; three halvings each. rk4 is asymptotic from 1/8 s (errors
  // 2.3e-5 .. 5.6e-9; measured 4.01, 4.01, 4.00). rkmk4's error is 10x smaller at
  // coarse steps and reaches its order 4 from below (measured 3.11, 3.34, 3.76 for
  // 1/4 -> 1/32 s, then 3.89, 3.95, 3.98 for 1/32 -> 1/256 s, errors 1.6e-8 .. 4.4e-12,
  // above the ~1.5e-13 rounding floor), so its fit starts at 1/32 s.
  struct Fit {
    const char* method;
    double coarse_step;
  };
  for (const Fit& fit : {Fit{"rk4", 1.0 / 8}, Fit{"rkmk4", 1.0 / 32}}) {
    const std::string label = std::string("krogh_") + fit.method;
    std::vector<double> e;
    for (int k = 0; k < 4; ++k) {
      IntegratorSettings s;
      s.step = fit.coarse_step / (1 << k);
      e.push_back(RunKrogh(fit.method, s));
    }
    for (std::size_t k = 0; k + 1 < e.size(); ++k) {
      const double observed = std::log2(e[k] / e[k + 1]);
      ::testing::Test::RecordProperty(label + "_order_" + std::to_string(k), Fmt(observed));
      EXPECT_NEAR(observed, 4.0, kOrderTolerance) << label << ": " << e[k] << " -> " << e[k + 1];
    }
    ::testing::Test::RecordProperty(label + "_error_coarse", Fmt(e.front()));
    ::testing::Test::RecordProperty(label + "_error_fine", Fmt(e.back()));
  }
}

// ---------------------------------------------------------------------------------
// (b) Seed appendix B: x'' + 2 alpha x' + beta x = 0, x(0) = x0, x'(0) = v0, on [0, 30]
// (h = 0.2 in the thesis), as y = (x, x') with y' = (x', -2 alpha x' - beta x).

using Vec2 = Eigen::Matrix<double, 2, 1>;

constexpr double kOscillatorHorizon = 30.0;  // [s]
constexpr double kThesisStep = 0.2;          // [s]

struct Oscillator {
  std::string name;
  double alpha;
  double beta;
  double x0 = 1.0;
  double v0 = 0.0;
};

/// Closed form of (x, x') for every regime. Roots r = -alpha +- sqrt(alpha^2 - beta).
Vec2 OscillatorExact(const Oscillator& o, double t) {
  const double a = o.alpha;
  const double b = o.beta;
  const double d = a * a - b;
  const double decay = std::exp(-a * t);
  if (d < 0.0) {  // underdamped: x = e^(-a t) (x0 cos wt + (v0 + a x0)/w sin wt)
    const double w = std::sqrt(-d);
    const double c = std::cos(w * t);
    const double s = std::sin(w * t);
    return Vec2(decay * (o.x0 * c + (o.v0 + a * o.x0) / w * s),
                decay * (o.v0 * c - (a * o.v0 + b * o.x0) / w * s));
  }
  if (d == 0.0) {  // critical: x = e^(-a t) (x0 + (v0 + a x0) t)
    const double c = o.v0 + a * o.x0;
    return Vec2(decay * (o.x0 + c * t), decay * (o.v0 - a * c * t));
  }
  // overdamped (beta = 0 included: r1 = 0): x = c1 e^(r1 t) + c2 e^(r2 t)
  const double s = std::sqrt(d);
  const double r1 = -a + s;
  const double r2 = -a - s;
  const double c1 = (o.v0 - r2 * o.x0) / (2.0 * s);
  const double c2 = (r1 * o.x0 - o.v0) / (2.0 * s);
  const double e1 = std::exp(r1 * t);
  const double e2 = std::exp(r2 * t);
  return Vec2(c1 * e1 + c2 * e2, c1 * r1 * e1 + c2 * r2 * e2);
}

/// The thesis's figures use (alpha, beta) = (1, 0.1) [Fig. B.1, captioned "damped"; with
/// alpha^2 > beta it is overdamped], (1, 0) [Fig. B.2, "free": no restoring force, x
/// tends to a constant] and (1, 1) [Fig. B.3, critically damped, captioned
/// "supercritical"]. The issue names the cases underdamped / free / overdamped, and none
/// of the figures is underdamped, so (0.1, 1) is added. With the thesis's x'(0) = 0 the
/// free case is the trivial x = 1 for every method (checked separately); its order test
/// starts from x'(0) = 1 instead (x tends to 1 + v0 / (2 alpha) = 1.5).
std::vector<Oscillator> OscillatorCases() {
  return {{"overdamped_fig_B1", 1.0, 0.1},
          {"free_fig_B2_moving", 1.0, 0.0, 1.0, 1.0},
          {"critical_fig_B3", 1.0, 1.0},
          {"underdamped", 0.1, 1.0}};
}

auto OscillatorRhs(const Oscillator& o) {
  return [a = o.alpha, b = o.beta](double /*t*/, const Vec2& y) {
    return Vec2(y[1], -2.0 * a * y[1] - b * y[0]);
  };
}

/// Max over t = i * h_grid (i >= 1) of the max-norm error of (x, x') for fixed steps h,
/// h_grid a multiple of h.
double OscillatorError(const ButcherTableau& tab, const Oscillator& o, double h, double h_grid) {
  const auto f = OscillatorRhs(o);
  const long n = std::lround(kOscillatorHorizon / h);
  const long every = std::lround(h_grid / h);
  Vec2 y(o.x0, o.v0);
  double worst = 0.0;
  for (long i = 1; i <= n; ++i) {
    y = RkStep<2>(tab, f, static_cast<double>(i - 1) * h, y, h);
    if (i % every == 0) {
      const Vec2 exact = OscillatorExact(o, static_cast<double>(i) * h);
      worst = std::max(worst, (y - exact).cwiseAbs().maxCoeff());
    }
  }
  return worst;
}

TEST(ClassicProblemsTest, OscillatorClosedFormSolvesTheOde) {
  // The oracle: initial values, and the ODE by central differences.
  constexpr double kDiffStep = 1e-5;
  // Truncation kDiffStep^2 / 6 |x'''| (|x'''| <= 1.95^3, the fastest root) <= 2e-10,
  // plus rounding ~1e-16 / kDiffStep.
  constexpr double kDiffTolerance = 1e-9;
  std::vector<Oscillator> cases = OscillatorCases();
  cases.push_back({"free_fig_B2", 1.0, 0.0});
  for (const Oscillator& o : cases) {
    const Vec2 y0 = OscillatorExact(o, 0.0);
    EXPECT_NEAR(y0[0], o.x0, 1e-15) << o.name;
    EXPECT_NEAR(y0[1], o.v0, 1e-15) << o.name;
    const auto f = OscillatorRhs(o);
    for (double t = 0.1; t < kOscillatorHorizon; t += 0.7) {
      const Vec2 fd =
          (OscillatorExact(o, t + kDiffStep) - OscillatorExact(o, t - kDiffStep)) / (2 * kDiffStep);
      EXPECT_LT((fd - f(t, OscillatorExact(o, t))).cwiseAbs().maxCoeff(), kDiffTolerance)
          << o.name << " t = " << t;
    }
  }
}

TEST(ClassicProblemsTest, FreeOscillatorAtRestStaysAtRest) {
  // Fig. B.2 with the thesis's x'(0) = 0: y = (1, 0) is an equilibrium, and every
  // tableau must keep it exactly (all stages are zero).
  const Oscillator o{"free_fig_B2", 1.0, 0.0};
  for (const ButcherTableau* tab :
       {&ExplicitEuler(), &ClassicRk4(), &DormandPrince54(), &Fehlberg78()}) {
    EXPECT_EQ(OscillatorError(*tab, o, kThesisStep, kThesisStep), 0.0) << tab->name;
  }
}

struct OrderCheck {
  const ButcherTableau* tableau;
  int p;
  double h0;     // [s] largest step of the fit
  int halvings;  // number of ratios e(h)/e(h/2) checked
  double below;  // allowed observed order below p
  double above;  // allowed observed order above p
};

// Step ranges and bands, with the orders measured over the four cases:
// - Euler: from 0.05 s (0.2 / 4), three halvings; measured 1.01..1.10. At 0.2 s the
//   underdamped case is not yet asymptotic: |1 + h lambda| = 1 exactly there (Euler is
//   neutrally stable), ratio 1.25.
// - RK4: from 0.1 s, three halvings; measured 4.00..4.12. At 0.2 s the overdamped fast
//   root (-1.95 1/s, h lambda = -0.39) still bends the ratio to 4.48.
// - DP5: from 0.1 s, two halvings (errors down to ~1e-12); measured 5.01..5.23.
// - RKF78: 0.4 -> 0.2 s (errors 1e-9 .. 5e-12; one more halving reaches the rounding
//   floor, 3e-15 .. 3e-14). The decaying cases are pre-asymptotic there (the next error
//   term, ~h lambda relative, raises the ratio to 8.3..8.6; measured 7.98 underdamped),
//   and no double-precision step range avoids that; so the band is one-sided: clearly
//   above 7 (propagating the seventh-order b_hat by mistake would show 7) and below 9.
std::vector<OrderCheck> OrderChecks() {
  return {{&ExplicitEuler(), 1, kThesisStep / 4, 3, 0.15, 0.15},
          {&ClassicRk4(), 4, kThesisStep / 2, 3, 0.2, 0.2},
          {&DormandPrince54(), 5, kThesisStep / 2, 2, 0.2, 0.3},
          {&Fehlberg78(), 8, 2 * kThesisStep, 1, 0.4, 0.9}};
}

TEST(ClassicProblemsTest, OscillatorOrdersOfEveryTableau) {
  constexpr double kSmallestFittedError = 1e-13;  // 30x the rounding floor (~3e-15)
  for (const Oscillator& o : OscillatorCases()) {
    for (const OrderCheck& c : OrderChecks()) {
      std::vector<double> e;
      for (int k = 0; k <= c.halvings; ++k) {
        e.push_back(OscillatorError(*c.tableau, o, c.h0 / (1 << k), c.h0));
      }
      for (int k = 0; k < c.halvings; ++k) {
        ASSERT_GT(e[k + 1], kSmallestFittedError) << o.name << " " << c.tableau->name;
        const double observed = std::log2(e[k] / e[k + 1]);
        const std::string label = o.name + "_" + c.tableau->name;
        ::testing::Test::RecordProperty(label + "_order_" + std::to_string(k), Fmt(observed));
        EXPECT_GT(observed, c.p - c.below) << label << ": " << e[k] << " -> " << e[k + 1];
        EXPECT_LT(observed, c.p + c.above) << label << ": " << e[k] << " -> " << e[k + 1];
      }
    }
  }
}

TEST(ClassicProblemsTest, ThesisFirstRk4StepIsTheUnderdampedCase) {
  // Seed section B.3 prints the "correct" first RK4 step (h = 0.2, x(0) = 1, x'(0) = 0)
  // as z(2) = -0.194746, y(2) = 0.980331 (y = x, z = x'). Those digits come from
  // (alpha, beta) = (0.1, 1) with the correct stage y_c4 = y + h k3; not from the
  // (1, 0.1) of Fig. B.1 (which gives 0.998241, -0.016469), nor from the listing's typo
  // y_c4 = y + h + k3 (which gives z = -0.198799).
  constexpr double kPrintedDigits = 5e-7;  // half a unit in the 6th printed decimal
  const Oscillator underdamped{"underdamped", 0.1, 1.0};
  const Vec2 y1 =
      RkStep<2>(ClassicRk4(), OscillatorRhs(underdamped), 0.0, Vec2(1.0, 0.0), kThesisStep);
  EXPECT_NEAR(y1[0], 0.980331, kPrintedDigits);
  EXPECT_NEAR(y1[1], -0.194746, kPrintedDigits);
  const Oscillator fig_b1{"overdamped_fig_B1", 1.0, 0.1};
  const Vec2 y1_b1 =
      RkStep<2>(ClassicRk4(), OscillatorRhs(fig_b1), 0.0, Vec2(1.0, 0.0), kThesisStep);
  EXPECT_GT(std::abs(y1_b1[1] - (-0.194746)), 0.1);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::integrators
