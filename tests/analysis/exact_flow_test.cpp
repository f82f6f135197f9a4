// Dense output of the `exact` stepper: output samples on rigid steps come from a
// Chebyshev interpolant of the closed form (ExactFlowStepper::DenseSample, chebyshev.h).
// Every sample must agree with a direct FreeBodySolution evaluation to a few ulp, and the
// flips (located on the closed form itself) must be bit for bit those of a run whose
// samples are the closed form, for the wing nut and for bodies at 1 - k^2 ~ 1e-12.

#include "deploysim/analysis/exact_flow.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/quaternion.h"
#include "test_support.h"

// The independent double-double Taylor reference of the benchmarks (header only, no code
// shared with src/).
#include "../../bench/free_body_reference.h"

namespace deploysim::analysis {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using integrators::State;

// The closed form's own values carry the rounding of its elliptic argument
// u = lambda (t - t0) + u0 (|u0| <= 2 K) and of its attitude angle gamma (|gamma| ~ |w| t),
// ~eps |u| |H| and ~eps |gamma| rad, growing with t (~3e-14 and ~1e-13 at t ~ 40 s): no
// smooth interpolant follows that, so the samples are compared with the closed form in
// units of it, and with the independent reference, against which the interpolated
// samples must be as accurate as the closed form's. Measured (x86-64, -O3): |dH|/|H| up to
// 1.05 eps (1 + 2 K + lambda t), attitude up to 4.1 eps (1 + |w| t) rad; against the
// reference at most 1.4 times the closed form's error. Bounds a few times above.
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kHRoundings = 3.0;         // |dH|/|H| in units of eps (1 + 2 K + lambda t)
constexpr double kAttitudeRoundings = 8.0;  // attitude [rad] in units of eps (1 + |w| t)
constexpr double kReferenceRatio = 2.0;     // error against the reference: interpolated /
                                            // closed form, plus a few ulp
constexpr double kUlps = 1e-15;

/// `exact` with the closed form for every output sample (the behaviour before the
/// interpolant): every method forwards, DenseSample keeps the default (Dense).
class DirectExact final : public integrators::Stepper {
 public:
  DirectExact() : inner_(MakeStepper("exact")) {}
  const integrators::StepperInfo& info() const override { return inner_->info(); }
  std::unique_ptr<integrators::StepperWorkspace> NewWorkspace() const override {
    return inner_->NewWorkspace();
  }
  integrators::StepAttempt Step(const integrators::Problem& p,
                                const State& y,
                                double h,
                                const integrators::Tolerances& tol,
                                integrators::StepperWorkspace& ws) const override {
    return inner_->Step(p, y, h, tol, ws);
  }
  void Accept(const integrators::Problem& p,
              const State& y0,
              const State& y1,
              integrators::StepperWorkspace& ws) const override {
    inner_->Accept(p, y0, y1, ws);
  }
  State Dense(const integrators::Problem& p,
              double t,
              const integrators::Tolerances& tol,
              integrators::StepperWorkspace& ws) const override {
    return inner_->Dense(p, t, tol, ws);
  }
  bool DenseIsExact(const integrators::StepperWorkspace& ws) const override {
    return inner_->DenseIsExact(ws);
  }
  double MaxStep(const integrators::Problem& p,
                 const State& y,
                 integrators::StepperWorkspace& ws) const override {
    return inner_->MaxStep(p, y, ws);
  }

 private:
  std::unique_ptr<integrators::Stepper> inner_;
};

struct Comparison {
  double H = 0.0;    // max |dH_B| / M of the samples against the closed form
  double att = 0.0;  // max attitude angle [rad] against the closed form
  double H_roundings = 0.0, att_roundings = 0.0;  // the same in units of the rounding
  // Errors against the independent reference: the interpolated and the closed-form run.
  double ref_H = 0.0, ref_att = 0.0, direct_ref_H = 0.0, direct_ref_att = 0.0;
  std::size_t samples = 0, differing = 0, flips = 0;
};

/// Runs `exact` and DirectExact over [0, t_end] with output every dt and the flip event;
/// checks the flips are bit for bit equal and compares the samples with the closed form
/// and with the independent reference.
Comparison Compare(const math::Vec3& moments,
                   const math::Vec3& H0,
                   const math::Quat& q0,
                   double t_end,
                   double dt) {
  const math::InertiaTensor J = math::InertiaTensor::FromPrincipalMoments(moments);
  const dynamics::ConstantInertia source(J);
  const FreeBodySolution sol(J, H0, q0, 0.0);
  const bench::FreeBodyReference ref(moments, H0, q0, 0.0, t_end);
  const std::vector<double> grid = integrators::UniformGrid(0.0, t_end, dt);
  integrators::IntegratorSettings st;
  st.tolerances = {1e-12, 1e-14};
  const auto fast = MakeStepper("exact");
  const DirectExact direct;
  const State s0{0.0, H0, q0};
  const auto r = integrators::Integrate(*fast, st, source, s0, t_end, grid, {FlipEvent(J)});
  const auto d = integrators::Integrate(direct, st, source, s0, t_end, grid, {FlipEvent(J)});
  const auto n = integrators::Integrate(*fast, st, source, s0, t_end, {}, {FlipEvent(J)});
  EXPECT_EQ(r.termination, integrators::Termination::kReachedEnd);
  EXPECT_EQ(r.samples.size(), grid.size());
  EXPECT_EQ(d.samples.size(), grid.size());
  // Flips: the same bits with the interpolated output, with the closed-form output and
  // with no output at all.
  EXPECT_EQ(r.events.size(), d.events.size());
  EXPECT_EQ(r.events.size(), n.events.size());
  for (std::size_t i = 0; i < std::min({r.events.size(), d.events.size(), n.events.size()}); ++i) {
    EXPECT_EQ(r.events[i].t, d.events[i].t) << i;
    EXPECT_EQ(r.events[i].t, n.events[i].t) << i;
    EXPECT_TRUE(integrators::SameBits(r.events[i].state, d.events[i].state)) << i;
  }
  EXPECT_TRUE(integrators::SameBits(r.final_state, d.final_state));
  Comparison c;
  c.flips = r.events.size();
  const double M = H0.norm();
  for (std::size_t i = 0; i < std::min(r.samples.size(), d.samples.size()); ++i) {
    const State& y = r.samples[i];
    const math::Vec3 H = sol.H_B(y.t);
    const math::Quat q = sol.q_NB(y.t).normalized();
    c.H = std::max(c.H, (y.H_B - H).norm() / M);
    c.att = std::max(c.att, math::AngleBetween(y.q_NB, q));
    const double K = 0.25 * sol.lambda() * sol.period();
    const double u_scale = kEps * (1.0 + 2.0 * K + sol.lambda() * y.t);
    const double gamma_scale = kEps * (1.0 + sol.w_NB_B(0.0).norm() * y.t);
    c.H_roundings = std::max(c.H_roundings, (y.H_B - H).norm() / M / u_scale);
    c.att_roundings = std::max(c.att_roundings, math::AngleBetween(y.q_NB, q) / gamma_scale);
    const math::Vec3 H_ref = ref.H_B(y.t);
    const math::Quat q_ref = ref.q_NB(y.t).normalized();
    c.ref_H = std::max(c.ref_H, (y.H_B - H_ref).norm() / M);
    c.ref_att = std::max(c.ref_att, math::AngleBetween(y.q_NB, q_ref));
    c.direct_ref_H = std::max(c.direct_ref_H, (d.samples[i].H_B - H_ref).norm() / M);
    c.direct_ref_att = std::max(c.direct_ref_att, math::AngleBetween(d.samples[i].q_NB, q_ref));
    if (!integrators::SameBits(y, d.samples[i])) ++c.differing;
  }
  c.samples = r.samples.size();
  return c;
}

/// Principal momentum (a, 1, a rho) M0 on an orbit with 1 - k^2 ~= mc next to the
/// intermediate axis (the wing nut's situation); I ascending.
math::Vec3 NearSeparatrix(const math::Vec3& I, double mc, bool minor, double M0) {
  const double g21 = I[1] - I[0], g32 = I[2] - I[1], g31 = I[2] - I[0];
  const double rho_sep = std::sqrt(g21 / I[0] * I[2] / g32);
  const double rho = rho_sep * (minor ? 0.6 : 2.0);
  const double c = g21 / I[0] - rho * rho * g32 / I[2];
  const double a2 = minor
                        ? mc * g21 * g32 / (I[1] * (g31 * c - mc * g21 * g31 / I[0]))
                        : mc * g32 * g21 / (I[1] * (-g31 * c - mc * g32 * rho * rho * g31 / I[2]));
  const double a = std::sqrt(a2);
  return math::Vec3(a, 1.0, a * rho) * M0;
}

void Report(const std::string& name, const Comparison& c) {
  ::testing::Test::RecordProperty(name + "_max_H", math::FormatNumber(c.H));
  ::testing::Test::RecordProperty(name + "_max_attitude", math::FormatNumber(c.att));
  std::printf(
      "%s: %zu samples (%zu from the interpolant differ in bits), %zu flips; against the "
      "closed form: max |dH|/M %.2e, attitude %.2e rad (%.2f and %.2f roundings); against the "
      "reference: "
      "interpolated "
      "%.2e, %.2e rad, closed form %.2e, %.2e rad\n",
      name.c_str(), c.samples, c.differing, c.flips, c.H, c.att, c.H_roundings, c.att_roundings,
      c.ref_H, c.ref_att, c.direct_ref_H, c.direct_ref_att);
}

void ExpectAccurate(const Comparison& c) {
  EXPECT_LT(c.H_roundings, kHRoundings);
  EXPECT_LT(c.att_roundings, kAttitudeRoundings);
  EXPECT_LE(c.ref_H, kReferenceRatio * c.direct_ref_H + kUlps);
  EXPECT_LE(c.ref_att, kReferenceRatio * c.direct_ref_att + kUlps);
  EXPECT_GT(c.differing, c.samples / 2);  // the interpolant is in use
}

TEST(ExactDenseTest, WingNutSamplesAgreeWithTheClosedFormToRounding) {
  const Comparison c =
      Compare(testing::WingNutMoments(), testing::WingNutH0(), math::Quat::Identity(), 40.0, 0.01);
  Report("wing_nut", c);
  EXPECT_EQ(c.flips, 11u);
  ExpectAccurate(c);
}

TEST(ExactDenseTest, NearSeparatrixSamplesAgreeWithTheClosedFormToRounding) {
  const math::Vec3 I(0.699e-6, 2.741e-6, 3.036e-6);
  const math::Quat q0 = math::Quat(0.3, -0.5, 0.7, 0.4).normalized();
  for (bool minor : {true, false}) {
    for (double mc : {1e-12, 1e-15}) {
      const math::Vec3 H0 = NearSeparatrix(I, mc, minor, 2.1252e-5);
      const FreeBodySolution sol(math::InertiaTensor::FromPrincipalMoments(I), H0, q0, 0.0);
      ASSERT_LT(sol.complementary_parameter(), 10 * mc);
      ASSERT_GT(sol.complementary_parameter(), 0.1 * mc);
      // Two and a half periods: five flips, each a steep sech-like pulse of H_B.
      const double t_end = 2.5 * sol.period();
      const Comparison c = Compare(I, H0, q0, t_end, 0.01);
      char name[32];
      std::snprintf(name, sizeof name, "%s_mc%g", minor ? "minor" : "major", mc);
      Report(name, c);
      EXPECT_EQ(c.flips, 5u);
      ExpectAccurate(c);
    }
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::analysis
