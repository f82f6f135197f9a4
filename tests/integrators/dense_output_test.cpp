// The continuous extensions (Stepper::Dense, dense_output.h): the order of the
// Dormand-Prince extension, and for every method the interpolant's error against the
// method's own partial steps over whole runs at the mission's tolerance.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/integrators/factory.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/quaternion.h"
#include "test_support.h"

namespace deploysim::integrators {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

std::string Fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3g", x);
  return buf;
}

// A generic tumbling body (no symmetry, far from the separatrix).
const math::Vec3 kMoments(3.0, 2.0, 1.0);
const math::Vec3 kH0(0.6, 1.1, 1.7);

struct Deviation {
  double H = 0.0;      // max |dH| / |H|
  double angle = 0.0;  // [rad]
};

// The accepted steps of a run of `method`; then, step by step on a fresh workspace, the
// continuous extension at 9 interior points against the method's partial step there.
Deviation DenseAgainstPartialSteps(const std::string& method,
                                   const dynamics::InertiaSource& source,
                                   const State& initial,
                                   double t_end,
                                   const IntegratorSettings& settings) {
  const std::unique_ptr<Stepper> stepper = MakeNumericalStepper(method);
  std::vector<State> accepted{initial};
  const IntegrationResult r = Integrate(*stepper, settings, source, initial, t_end, {}, {},
                                        [&](const State& y) { accepted.push_back(y); });
  EXPECT_EQ(r.termination, Termination::kReachedEnd) << r.message;
  Problem problem(source, initial.q_NB * initial.H_B);
  problem.SetSegment(initial.t, t_end);
  const std::unique_ptr<StepperWorkspace> ws = stepper->NewWorkspace();
  Deviation d;
  const double M = initial.H_B.norm();
  for (std::size_t i = 0; i + 1 < accepted.size(); ++i) {
    const State& y0 = accepted[i];
    const double h = accepted[i + 1].t - y0.t;
    const State y1 = stepper->Step(problem, y0, h, settings.tolerances, *ws).result;
    stepper->Accept(problem, y0, y1, *ws);
    for (int k = 1; k < 10; ++k) {
      const double t = y0.t + 0.1 * k * h;
      const State dense = stepper->Dense(problem, t, settings.tolerances, *ws);
      const State exact = stepper->Step(problem, y0, t - y0.t, settings.tolerances, *ws).result;
      d.H = std::max(d.H, (dense.H_B - exact.H_B).norm() / M);
      d.angle = std::max(d.angle, math::AngleBetween(dense.q_NB, exact.q_NB));
    }
  }
  return d;
}

TEST(DenseOutputTest, InterpolantsAgreeWithPartialStepsAtTheMissionTolerance) {
  // Measured (rtol 1e-10, atol 1e-12, 20 s of the generic body; H relative / angle rad):
  //   dopri5 6.6e-12 / 2.4e-11, rkmk-dopri5 1.0e-10 / 1.3e-10 (the fourth-order
  //   extension, below the methods' own global error); rkf78 4.0e-14 / 3.2e-13,
  //   rkmk-rkf78 6.4e-13 / 8.6e-13 (Hermite on 5 nodes; on 3 nodes, the quintic, 2.8e-9
  //   and 1.4e-8, on 4 nodes 1.7e-12 and 2.4e-11); fixed step (h = 0.01 s, cubic
  //   Hermite) rk4 2.8e-11 / 3.4e-11, rkmk4 1.0e-11, split4 2.3e-11; thesis-euler
  //   (h = 1e-3 s) 8.6e-8 / 4.6e-11.
  const dynamics::ConstantInertia source(math::InertiaTensor::FromPrincipalMoments(kMoments));
  const State initial{0.0, kH0, math::Quat(0.8, 0.1, -0.3, 0.5).normalized()};
  struct Case {
    const char* method;
    double step;
    double tolerance;  // on both H and angle
  };
  const std::vector<Case> cases = {
      {"dopri5", 0.0, 1e-10},     {"rkf78", 0.0, 1.5e-12},      {"rkmk-dopri5", 0.0, 5e-10},
      {"rkmk-rkf78", 0.0, 4e-12}, {"rk4", 0.01, 1.5e-10},       {"rkmk4", 0.01, 5e-11},
      {"split4", 0.01, 1e-10},    {"thesis-euler", 1e-3, 4e-7},
  };
  for (const Case& c : cases) {
    IntegratorSettings s;
    s.step = c.step;
    s.tolerances = {1e-10, 1e-12};
    const Deviation d = DenseAgainstPartialSteps(c.method, source, initial, 20.0, s);
    ::testing::Test::RecordProperty(std::string(c.method) + "_dense_H", Fmt(d.H));
    ::testing::Test::RecordProperty(std::string(c.method) + "_dense_angle", Fmt(d.angle));
    std::printf("%-14s dense vs partial step: H %.3g, angle %.3g rad\n", c.method, d.H, d.angle);
    EXPECT_LT(d.H, c.tolerance) << c.method;
    EXPECT_LT(d.angle, c.tolerance) << c.method;
  }
}

// The Dormand-Prince continuous extension is of order 4: its error at theta = 1/2 of
// one step from a fixed state falls like h^5 (a wrong coefficient would leave h^4 or
// less). The reference is rkf78 at rtol 1e-15.
TEST(DenseOutputTest, DormandPrinceExtensionIsFourthOrder) {
  const dynamics::ConstantInertia source(math::InertiaTensor::FromPrincipalMoments(kMoments));
  const State y0{0.0, kH0, math::Quat::Identity()};
  for (const char* method : {"dopri5", "rkmk-dopri5"}) {
    const std::unique_ptr<Stepper> stepper = MakeNumericalStepper(method);
    const std::unique_ptr<Stepper> reference = MakeNumericalStepper("rkf78");
    IntegratorSettings ref_settings;
    ref_settings.tolerances = {1e-15, 1e-17};
    std::vector<double> errors;
    for (double h = 0.2; h > 0.01; h *= 0.5) {
      Problem problem(source, y0.q_NB * y0.H_B);
      problem.SetSegment(0.0, 10.0);
      const std::unique_ptr<StepperWorkspace> ws = stepper->NewWorkspace();
      const State y1 = stepper->Step(problem, y0, h, ref_settings.tolerances, *ws).result;
      stepper->Accept(problem, y0, y1, *ws);
      const double t = 0.5 * h;
      const State dense = stepper->Dense(problem, t, ref_settings.tolerances, *ws);
      const State ref = Integrate(*reference, ref_settings, source, y0, t).final_state;
      errors.push_back((dense.H_B - ref.H_B).norm() / kH0.norm());
    }
    for (std::size_t k = 0; k + 1 < errors.size(); ++k) {
      const double order = std::log2(errors[k] / errors[k + 1]);
      ::testing::Test::RecordProperty(std::string(method) + "_dense_order_" + std::to_string(k),
                                      Fmt(order));
      // Local error h^5 (measured 5.12, 5.06, 5.03, 5.02 for dopri5 and 5.22, 5.09,
      // 5.04, 5.02 for rkmk-dopri5, h = 0.2 ... 0.0125 s).
      EXPECT_NEAR(order, 5.0, 0.3) << method << ": e = " << errors[k] << ", " << errors[k + 1];
    }
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::integrators
