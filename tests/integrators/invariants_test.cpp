// First integrals along the numerical solution (issue acceptance 3): the Lie-group
// methods keep |H_B| and h_N = R_NB H_B to rounding over 10^5 steps, also under a
// time-varying J(t). With constant J, rkmk4's energy error is at rounding level at a
// working step but drifts secularly (like h^5 t) at coarse steps; the symplectic
// splitting split4 is the Lie-group method whose energy error is bounded, not drifting
// (Split4EnergyErrorIsBoundedNotDrifting).
// By contrast the seed's explicit Euler drifts in |H|, and the vector-space RK4 does not
// hold |H_B| to rounding (which is why the Lie-group method exists).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/integrators/factory.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/quaternion.h"
#include "test_support.h"

namespace deploysim::integrators {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

// Issue acceptance 3: |H_B| and h_N to <= 1e-13 relative over 10^5 steps.
constexpr double kInvariantTolerance = 1e-13;
constexpr long kLongRunSteps = 100'000;

std::string Fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.4g", x);
  return buf;
}

/// Worst relative deviations of |H_B| and h_N from their initial values over every
/// accepted step, collected by the StepObserver.
struct InvariantMonitor {
  explicit InvariantMonitor(const State& initial)
      : H0(initial.H_B.norm()), h_N0(initial.q_NB.normalized() * initial.H_B) {}
  void operator()(const State& s) {
    ++steps;
    max_H_dev = std::max(max_H_dev, std::abs(s.H_B.norm() - H0) / H0);
    const math::Vec3 h_N = dynamics::InertialMomentum(s.q_NB, s.H_B);
    max_h_N_dev = std::max(max_h_N_dev, (h_N - h_N0).norm() / H0);
  }
  double H0;
  math::Vec3 h_N0;
  long steps = 0;
  double max_H_dev = 0.0;
  double max_h_N_dev = 0.0;
};

struct WingNut {
  math::InertiaTensor J = math::InertiaTensor::FromPrincipalMoments(testing::WingNutMoments());
  dynamics::ConstantInertia source{J};
  State initial{0.0, testing::WingNutH0(), math::Quat::Identity()};
};

dynamics::FunctionInertia SyntheticSource() {
  return dynamics::MakeSyntheticInertia(math::Vec3(1.0, 1.3, 1.6), math::Vec3(0.05, 0.08, 0.03),
                                        0.7, 0.3, math::Vec3(0.01, -0.02, 0.015));
}
const State kSyntheticInitial{0.0, math::Vec3(0.6, -0.9, 0.5),
                              math::ExpQuat(math::Vec3(0.2, -0.5, 0.3))};

InvariantMonitor RunMonitored(const std::string& method,
                              const IntegratorSettings& settings,
                              const dynamics::InertiaSource& source,
                              const State& initial,
                              double t_end) {
  const std::unique_ptr<Stepper> stepper = MakeNumericalStepper(method);
  InvariantMonitor monitor(initial);
  const IntegrationResult r = Integrate(*stepper, settings, source, initial, t_end, {}, {},
                                        [&monitor](const State& s) { monitor(s); });
  EXPECT_EQ(r.termination, Termination::kReachedEnd) << method << ": " << r.message;
  EXPECT_EQ(monitor.steps, r.stats.steps) << method;
  return monitor;
}

void ExpectInvariantsHeld(const std::string& label, const InvariantMonitor& m) {
  EXPECT_LE(m.max_H_dev, kInvariantTolerance) << label << " over " << m.steps << " steps";
  EXPECT_LE(m.max_h_N_dev, kInvariantTolerance) << label << " over " << m.steps << " steps";
  ::testing::Test::RecordProperty(label + "_steps", std::to_string(m.steps));
  ::testing::Test::RecordProperty(label + "_max_H_dev", Fmt(m.max_H_dev));
  ::testing::Test::RecordProperty(label + "_max_h_N_dev", Fmt(m.max_h_N_dev));
}

TEST(InvariantsTest, Rkmk4HoldsMomentumOnWingNutOver1e5Steps) {
  // 10^5 steps of 4e-4 s: 40 s, all eleven flips of docs/design.md section 6.
  constexpr double kStep = 4e-4;
  WingNut w;
  IntegratorSettings s;
  s.step = kStep;
  const InvariantMonitor m = RunMonitored("rkmk4", s, w.source, w.initial, kLongRunSteps * kStep);
  EXPECT_EQ(m.steps, kLongRunSteps);
  ExpectInvariantsHeld("wing_nut_rkmk4", m);
}

TEST(InvariantsTest, Rkmk4HoldsMomentumUnderTimeVaryingInertiaOver1e5Steps) {
  // 10^5 steps of 1e-3 s: 100 s, eleven periods of J(t).
  constexpr double kStep = 1e-3;
  const dynamics::FunctionInertia source = SyntheticSource();
  IntegratorSettings s;
  s.step = kStep;
  const InvariantMonitor m =
      RunMonitored("rkmk4", s, source, kSyntheticInitial, kLongRunSteps * kStep);
  EXPECT_EQ(m.steps, kLongRunSteps);
  ExpectInvariantsHeld("synthetic_rkmk4", m);
}

TEST(InvariantsTest, RkmkRkf78HoldsMomentumOnWingNutAndUnderTimeVaryingInertia) {
  // Horizons long enough for >= 5e4 adaptive steps at rtol 1e-12 (measured: 9934 steps
  // per 400 s on the wing nut, 2551 per 1000 s on the synthetic body).
  constexpr double kWingNutHorizon = 4000.0;     // [s]
  constexpr double kSyntheticHorizon = 20000.0;  // [s]
  constexpr long kMinSteps = 50'000;
  IntegratorSettings s;
  s.tolerances = {1e-12, 1e-14};
  WingNut w;
  const InvariantMonitor m_w = RunMonitored("rkmk-rkf78", s, w.source, w.initial, kWingNutHorizon);
  EXPECT_GE(m_w.steps, kMinSteps);
  ExpectInvariantsHeld("wing_nut_rkmk-rkf78", m_w);
  const dynamics::FunctionInertia source = SyntheticSource();
  const InvariantMonitor m_s =
      RunMonitored("rkmk-rkf78", s, source, kSyntheticInitial, kSyntheticHorizon);
  EXPECT_GE(m_s.steps, kMinSteps);
  ExpectInvariantsHeld("synthetic_rkmk-rkf78", m_s);
}

// Energy of a constant-J body along a fixed-step run: max |E - E0| / E0 over the first
// tenth of the run and over all of it, and at the end.
struct EnergyDrift {
  double first_tenth = 0.0;
  double whole = 0.0;
  double final = 0.0;
};

EnergyDrift MeasureEnergyDrift(const std::string& method,
                               const math::Vec3& moments,
                               const math::Vec3& H0,
                               double step,
                               double t_end) {
  const dynamics::ConstantInertia source(math::InertiaTensor::FromPrincipalMoments(moments));
  const dynamics::InertiaSample sample = source.Evaluate(0.0);
  const double E0 = dynamics::KineticEnergy(sample, H0);
  const double t_tenth = 0.1 * t_end;
  EnergyDrift d;
  IntegratorSettings s;
  s.step = step;
  const std::unique_ptr<Stepper> stepper = MakeNumericalStepper(method);
  const IntegrationResult r =
      Integrate(*stepper, s, source, State{0.0, H0, math::Quat::Identity()}, t_end, {}, {},
                [&](const State& y) {
                  const double dev = std::abs(dynamics::KineticEnergy(sample, y.H_B) - E0) / E0;
                  d.whole = std::max(d.whole, dev);
                  if (y.t <= t_tenth) d.first_tenth = std::max(d.first_tenth, dev);
                  d.final = dev;
                });
  EXPECT_EQ(r.termination, Termination::kReachedEnd) << method;
  return d;
}

// A generic asymmetric body far from the separatrix (|w| ~ 0.6 rad/s, period ~ 20 s).
const math::Vec3 kGenericMoments(1.0, 1.6, 2.2);  // [kg m^2]
const math::Vec3 kGenericH0(0.9, 0.3, 0.5);       // [kg m^2/s]

TEST(InvariantsTest, Rkmk4EnergyErrorStaysAtRoundingOnWingNutOver1e5Steps) {
  // At the step that resolves the wing nut (4e-4 s, 10^5 steps = 40 s, eleven flips)
  // rkmk4's energy error is rounding: measured 1.6e-14. Bound: 1e-13, the issue's
  // tolerance for the momentum invariants.
  constexpr double kStep = 4e-4;
  constexpr double kEnergyTolerance = 1e-13;
  const EnergyDrift d = MeasureEnergyDrift("rkmk4", testing::WingNutMoments(), testing::WingNutH0(),
                                           kStep, kLongRunSteps * kStep);
  ::testing::Test::RecordProperty("wing_nut_energy_max", Fmt(d.whole));
  EXPECT_LE(d.whole, kEnergyTolerance);
}

TEST(InvariantsTest, Rkmk4EnergyDriftIsSecularButHighOrderInStep) {
  // Issue acceptance 3 asks for an energy error that is "bounded, not drifting" with
  // constant J. That does not hold for rkmk4: classic RK4 in the Lie-algebra coordinates
  // is neither symmetric nor symplectic, and |E - E0| grows linearly in t (measured
  // whole-run / first-tenth maximum = 9.3 at h = 0.1 s over 1000 s; 10 is linear, ~1
  // bounded). What does hold: the drift rate falls like h^5 (measured 5.0; the h^4
  // term of the global error averages out over a period), so it is at rounding level
  // at working steps (previous test). This test pins both facts; if the growth check
  // fails, the method has become energy-conserving and the stronger claim can
  // be asserted instead.
  constexpr double kHorizon = 1000.0;     // [s], ~50 periods
  constexpr double kCoarseStep = 0.1;     // [s], 10^4 steps
  constexpr double kMinGrowth = 5.0;      // linear growth gives 10, a bounded error ~1
  constexpr double kMinDriftOrder = 3.8;  // at least the method's order 4 (-0.2)
  const EnergyDrift coarse =
      MeasureEnergyDrift("rkmk4", kGenericMoments, kGenericH0, kCoarseStep, kHorizon);
  const EnergyDrift fine =
      MeasureEnergyDrift("rkmk4", kGenericMoments, kGenericH0, 0.5 * kCoarseStep, kHorizon);
  const double growth = coarse.whole / coarse.first_tenth;
  const double drift_order = std::log2(coarse.final / fine.final);
  ::testing::Test::RecordProperty("generic_energy_first_tenth", Fmt(coarse.first_tenth));
  ::testing::Test::RecordProperty("generic_energy_whole", Fmt(coarse.whole));
  ::testing::Test::RecordProperty("generic_energy_growth", Fmt(growth));
  ::testing::Test::RecordProperty("generic_energy_drift_order", Fmt(drift_order));
  EXPECT_GT(growth, kMinGrowth) << coarse.first_tenth << " -> " << coarse.whole;
  EXPECT_GT(drift_order, kMinDriftOrder) << coarse.final << " -> " << fine.final;
}

TEST(InvariantsTest, Split4EnergyErrorIsBoundedNotDrifting) {
  // The symplectic, symmetric Lie-Poisson splitting (split4) is the Lie-group method
  // for which the "bounded, not drifting" holds with constant J: on the same
  // run that shows rkmk4's linear growth (10^4 steps over 1000 s) its energy error
  // oscillates with no trend, and h_N and |H_B| stay at rounding.
  constexpr double kHorizon = 1000.0;  // [s], ~50 periods
  constexpr double kStep = 0.1;        // [s]
  constexpr double kMaxGrowth = 2.0;   // bounded: whole-run max ~ first-tenth max
  const EnergyDrift d = MeasureEnergyDrift("split4", kGenericMoments, kGenericH0, kStep, kHorizon);
  ::testing::Test::RecordProperty("split4_energy_first_tenth", Fmt(d.first_tenth));
  ::testing::Test::RecordProperty("split4_energy_whole", Fmt(d.whole));
  EXPECT_LT(d.whole / d.first_tenth, kMaxGrowth) << d.first_tenth << " -> " << d.whole;
  // And it is fourth order: the energy error falls ~16x when the step halves.
  const EnergyDrift half =
      MeasureEnergyDrift("split4", kGenericMoments, kGenericH0, 0.5 * kStep, kHorizon);
  EXPECT_NEAR(std::log2(d.whole / half.whole), 4.0, 0.3);
}

TEST(InvariantsTest, Split4HoldsMomentumOver1e5Steps) {
  WingNut w;
  IntegratorSettings s;
  s.step = 4e-4;
  const std::unique_ptr<Stepper> stepper = MakeNumericalStepper("split4");
  const math::Vec3 h_N0 = w.initial.q_NB * w.initial.H_B;
  double worst = 0.0;
  long steps = 0;
  Integrate(*stepper, s, w.source, w.initial, kLongRunSteps * 4e-4, {}, {}, [&](const State& y) {
    ++steps;
    worst = std::max(worst, (y.q_NB * y.H_B - h_N0).norm() / h_N0.norm());
    worst = std::max(worst, std::abs(y.H_B.norm() / h_N0.norm() - 1.0));
  });
  EXPECT_EQ(steps, kLongRunSteps);
  EXPECT_LE(worst, 1e-13);
}

TEST(InvariantsTest, ThesisEulerMomentumDriftGrowsLinearly) {
  // The seed's baseline at a 10x coarser step than its 2e-5 s. Explicit Euler raises
  // |H|^2 by h^2 |H x w|^2 every step, which is large only during a flip: the drift is
  // a staircase, one stair per flip, and grows linearly on average (3 flips by 10 s,
  // 11 by 40 s: ratio 11/3 = 3.7; a bounded error would give ~1).
  constexpr double kStep = 2e-4;
  constexpr double kMinRatio = 3.0;
  constexpr double kMaxRatio = 4.5;
  // docs/design.md 6: drift 9.1e-4 at h = 2e-5 s over 40 s; the drift is first order in
  // h, so 10x that here. 5 % covers the O(h^2) term and the rounding of 9.1e-4.
  constexpr double kDesignDriftAt40s = 9.1e-4 * 10.0;
  constexpr double kDesignDriftTolerance = 0.05 * kDesignDriftAt40s;
  WingNut w;
  IntegratorSettings s;
  s.step = kStep;
  const std::vector<double> grid{10.0, 20.0, 30.0, 40.0};
  const std::unique_ptr<Stepper> stepper = MakeNumericalStepper("thesis-euler");
  const IntegrationResult r = Integrate(*stepper, s, w.source, w.initial, 40.0, grid);
  ASSERT_EQ(r.samples.size(), grid.size());
  std::vector<double> drift;
  for (const State& y : r.samples) {
    drift.push_back(y.H_B.norm() / w.initial.H_B.norm() - 1.0);
    ::testing::Test::RecordProperty("euler_drift_t" + Fmt(y.t), Fmt(drift.back()));
  }
  for (std::size_t i = 0; i + 1 < drift.size(); ++i) EXPECT_LT(drift[i], drift[i + 1]);
  const double ratio = drift.back() / drift.front();
  EXPECT_GT(ratio, kMinRatio);
  EXPECT_LT(ratio, kMaxRatio);
  EXPECT_NEAR(drift.back(), kDesignDriftAt40s, kDesignDriftTolerance);
}

TEST(InvariantsTest, VectorSpaceRk4DoesNotHoldMomentumAtCoarseStep) {
  // At a coarse step (the wing nut turns 0.078 rad per step) classic RK4 on (H_B, q_NB)
  // lets |H_B| and h_N wander by its truncation error (measured 1.4e-8 and 3.1e-7 over
  // 10 s), while rkmk4 at the same step holds both to rounding.
  constexpr double kStep = 1e-2;
  constexpr double kHorizon = 10.0;
  constexpr double kClearlyAboveRounding = 1e3 * kInvariantTolerance;
  WingNut w;
  IntegratorSettings s;
  s.step = kStep;
  const InvariantMonitor rk4 = RunMonitored("rk4", s, w.source, w.initial, kHorizon);
  ::testing::Test::RecordProperty("rk4_max_H_dev", Fmt(rk4.max_H_dev));
  ::testing::Test::RecordProperty("rk4_max_h_N_dev", Fmt(rk4.max_h_N_dev));
  EXPECT_GT(rk4.max_H_dev, kClearlyAboveRounding);
  EXPECT_GT(rk4.max_h_N_dev, kClearlyAboveRounding);
  ExpectInvariantsHeld("wing_nut_coarse_rkmk4",
                       RunMonitored("rkmk4", s, w.source, w.initial, kHorizon));
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::integrators
