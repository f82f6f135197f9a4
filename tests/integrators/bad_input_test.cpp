// Bad input to the integration driver (issue acceptance 7, integrator part): every
// invalid setting or argument throws std::invalid_argument whose message names the
// violated rule (STYLE.md: name the key, the value and the rule).

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/integrators/factory.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/math/inertia.h"
#include "test_support.h"

namespace deploysim::integrators {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kHorizon = 0.1;  // [s], short: valid runs must finish instantly

/// Runs f and expects std::invalid_argument whose what() contains every substring.
template <class F>
void ExpectInvalidArgument(F&& f,
                           const std::vector<std::string>& substrings,
                           const std::string& context) {
  try {
    f();
    ADD_FAILURE() << context << ": no exception";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    for (const std::string& s : substrings) {
      EXPECT_NE(what.find(s), std::string::npos)
          << context << ": message '" << what << "' lacks '" << s << "'";
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << context << ": wrong exception type: " << e.what();
  }
}

struct WingNut {
  math::InertiaTensor J = math::InertiaTensor::FromPrincipalMoments(testing::WingNutMoments());
  dynamics::ConstantInertia source{J};
  State initial{0.0, testing::WingNutH0(), math::Quat::Identity()};
};

std::vector<std::string> MethodsWhere(bool adaptive) {
  std::vector<std::string> out;
  for (const std::string& name : NumericalStepperNames()) {
    if (MakeNumericalStepper(name)->info().adaptive == adaptive) out.push_back(name);
  }
  return out;
}

IntegratorSettings ValidSettings(const Stepper& stepper) {
  IntegratorSettings s;
  if (!stepper.info().adaptive) s.step = 1e-3;
  return s;
}

TEST(BadInputTest, MethodListsAreAsDocumented) {
  // The loops below cover both kinds of method.
  EXPECT_EQ(MethodsWhere(false),
            (std::vector<std::string>{"thesis-euler", "rk4", "rkmk4", "split4"}));
  EXPECT_EQ(MethodsWhere(true),
            (std::vector<std::string>{"dopri5", "rkf78", "rkmk-dopri5", "rkmk-rkf78"}));
}

TEST(BadInputTest, ValidSettingsAreAccepted) {
  // Control: the baseline used by every case below runs.
  WingNut w;
  for (const std::string& name : NumericalStepperNames()) {
    const auto stepper = MakeNumericalStepper(name);
    const IntegrationResult r = Integrate(*stepper, ValidSettings(*stepper), w.source, w.initial,
                                          kHorizon, {0.0, kHorizon});
    EXPECT_EQ(r.termination, Termination::kReachedEnd) << name;
  }
}

TEST(BadInputTest, FixedStepNeedsFinitePositiveStep) {
  WingNut w;
  for (const std::string& name : MethodsWhere(false)) {
    const auto stepper = MakeNumericalStepper(name);
    for (double step : {0.0, -1e-3, kNaN, kInf}) {
      IntegratorSettings s;
      s.step = step;
      ExpectInvalidArgument(
          [&] { Integrate(*stepper, s, w.source, w.initial, kHorizon); },
          {"integrator " + name, "step = ", "rule: a fixed-step method needs a finite step > 0"},
          name + " step " + std::to_string(step));
    }
  }
}

TEST(BadInputTest, AdaptiveInitialStepIsZeroOrPositive) {
  WingNut w;
  for (const std::string& name : MethodsWhere(true)) {
    const auto stepper = MakeNumericalStepper(name);
    for (double step : {-1e-3, kNaN, kInf}) {
      IntegratorSettings s;
      s.step = step;
      ExpectInvalidArgument(
          [&] { Integrate(*stepper, s, w.source, w.initial, kHorizon); },
          {"integrator " + name, "the initial step is 0 (automatic) or finite > 0"},
          name + " step " + std::to_string(step));
    }
  }
}

TEST(BadInputTest, AdaptiveRtolInRange) {
  WingNut w;
  for (const std::string& name : MethodsWhere(true)) {
    const auto stepper = MakeNumericalStepper(name);
    for (double rtol : {0.0, -1e-8, kNaN, 1.0, 2.0, 1e-17, kInf}) {
      IntegratorSettings s;
      s.tolerances.rtol = rtol;
      ExpectInvalidArgument([&] { Integrate(*stepper, s, w.source, w.initial, kHorizon); },
                            {"integrator " + name, "rtol = ", "rule: 1e-16 <= rtol < 1"},
                            name + " rtol " + std::to_string(rtol));
    }
  }
}

TEST(BadInputTest, AdaptiveAtolPositiveAndFinite) {
  WingNut w;
  for (const std::string& name : MethodsWhere(true)) {
    const auto stepper = MakeNumericalStepper(name);
    for (double atol : {0.0, -1e-12, kNaN, kInf}) {
      IntegratorSettings s;
      s.tolerances.atol = atol;
      ExpectInvalidArgument([&] { Integrate(*stepper, s, w.source, w.initial, kHorizon); },
                            {"integrator " + name, "atol = ", "rule: atol > 0 and finite"},
                            name + " atol " + std::to_string(atol));
    }
  }
}

TEST(BadInputTest, MaxStepPositive) {
  WingNut w;
  for (const std::string& name : NumericalStepperNames()) {
    const auto stepper = MakeNumericalStepper(name);
    for (double max_step : {0.0, -1.0, kNaN}) {
      IntegratorSettings s = ValidSettings(*stepper);
      s.max_step = max_step;
      ExpectInvalidArgument([&] { Integrate(*stepper, s, w.source, w.initial, kHorizon); },
                            {"integrator " + name, "max_step = ", "rule: max_step > 0"},
                            name + " max_step " + std::to_string(max_step));
    }
  }
}

TEST(BadInputTest, MaxStepsPositive) {
  WingNut w;
  const auto stepper = MakeNumericalStepper("rk4");
  for (long max_steps : {0L, -5L}) {
    IntegratorSettings s = ValidSettings(*stepper);
    s.max_steps = max_steps;
    ExpectInvalidArgument([&] { Integrate(*stepper, s, w.source, w.initial, kHorizon); },
                          {"max_steps must be > 0"}, "max_steps " + std::to_string(max_steps));
  }
}

TEST(BadInputTest, EndTimeAfterStart) {
  WingNut w;
  for (const std::string& name : std::vector<std::string>{"rk4", "rkmk-rkf78"}) {
    const auto stepper = MakeNumericalStepper(name);
    const IntegratorSettings s = ValidSettings(*stepper);
    State start = w.initial;
    start.t = 2.0;
    for (double t_end : {2.0, 1.0, -3.0, kNaN, kInf}) {
      ExpectInvalidArgument([&] { Integrate(*stepper, s, w.source, start, t_end); },
                            {"end time must be finite and > start time"},
                            name + " t_end " + std::to_string(t_end));
    }
  }
}

TEST(BadInputTest, InitialStateFinite) {
  WingNut w;
  const auto stepper = MakeNumericalStepper("rkmk4");
  const IntegratorSettings s = ValidSettings(*stepper);
  std::vector<State> bad(4, w.initial);
  bad[0].H_B.y() = kNaN;
  bad[1].H_B.x() = kInf;
  bad[2].q_NB.w() = kNaN;
  bad[3].t = kNaN;
  for (std::size_t i = 0; i < bad.size(); ++i) {
    ExpectInvalidArgument([&] { Integrate(*stepper, s, w.source, bad[i], kHorizon); },
                          {"initial state must be finite"}, "bad state " + std::to_string(i));
  }
}

TEST(BadInputTest, OutputTimesAscendingAndInRange) {
  WingNut w;
  const auto stepper = MakeNumericalStepper("dopri5");
  const IntegratorSettings s = ValidSettings(*stepper);
  ExpectInvalidArgument(
      [&] {
        Integrate(*stepper, s, w.source, w.initial, kHorizon, {0.0, 0.05, 0.02});
      },
      {"output times must be ascending"}, "unsorted");
  ExpectInvalidArgument(
      [&] {
        Integrate(*stepper, s, w.source, w.initial, kHorizon, {-0.01, 0.05});
      },
      {"output times must lie within [t0, t_end]"}, "before t0");
  ExpectInvalidArgument(
      [&] {
        Integrate(*stepper, s, w.source, w.initial, kHorizon, {0.05, 2 * kHorizon});
      },
      {"output times must lie within [t0, t_end]"}, "after t_end");
}

// Regression tests for two input checks that were missing: a NaN inside the output
// times, and a zero initial quaternion.
TEST(BadInputTest, NaNOutputTimeIsRejected) {
  WingNut w;
  const auto stepper = MakeNumericalStepper("rk4");
  const IntegratorSettings s = ValidSettings(*stepper);
  ExpectInvalidArgument(
      [&] {
        Integrate(*stepper, s, w.source, w.initial, kHorizon, {0.0, kNaN, 0.05});
      },
      {"output times"}, "NaN output time");
}

TEST(BadInputTest, ZeroQuaternionIsRejected) {
  WingNut w;
  const auto stepper = MakeNumericalStepper("rkmk4");
  const IntegratorSettings s = ValidSettings(*stepper);
  State zero = w.initial;
  zero.q_NB = math::Quat(0.0, 0.0, 0.0, 0.0);
  ExpectInvalidArgument([&] { Integrate(*stepper, s, w.source, zero, kHorizon); }, {"initial"},
                        "zero quaternion");
}

TEST(BadInputTest, UnknownMethodNameListsTheValidOnes) {
  std::vector<std::string> expected{"unknown integrator 'nope'"};
  for (const std::string& name : NumericalStepperNames()) expected.push_back(name);
  ExpectInvalidArgument([] { MakeNumericalStepper("nope"); }, expected, "nope");
  // Names are exact: no case folding, no trimming.
  ExpectInvalidArgument([] { MakeNumericalStepper("RK4"); }, {"unknown integrator 'RK4'"}, "RK4");
  ExpectInvalidArgument([] { MakeNumericalStepper(" rk4"); }, {"unknown integrator ' rk4'"},
                        "leading space");
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::integrators
