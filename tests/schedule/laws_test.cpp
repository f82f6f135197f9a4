#include "deploysim/schedule/laws.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace deploysim::schedule {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

constexpr std::array<Law, 4> kAllLaws{Law::kStep, Law::kLinear, Law::kSmoothstep,
                                      Law::kMinimumJerk};
constexpr std::array<Law, 3> kContinuousLaws{Law::kLinear, Law::kSmoothstep, Law::kMinimumJerk};

/// Central differences with step kFdStep have truncation error ~ kFdStep^2 |s'''| / 6
/// (|s'''| <= 60 for minimum-jerk) plus rounding ~ 1e-16 / kFdStep.
constexpr double kFdStep = 1e-5;
constexpr double kFdTolerance = 1e-8;
/// Exact polynomial identities evaluated in double precision.
constexpr double kRoundoff = 1e-14;

TEST(LawsTest, EndpointValues) {
  for (Law law : kAllLaws) {
    SCOPED_TRACE(ToString(law));
    const LawValue v0 = EvaluateLaw(law, 0.0);
    const LawValue v1 = EvaluateLaw(law, 1.0);
    EXPECT_EQ(v0.s, 0.0);
    EXPECT_EQ(v1.s, 1.0);
  }
}

TEST(LawsTest, StepSwitchesImmediatelyAfterTheStart) {
  const LawValue v = EvaluateLaw(Law::kStep, 1e-300);
  EXPECT_EQ(v.s, 1.0);
  EXPECT_EQ(v.ds, 0.0);
  EXPECT_EQ(v.dds, 0.0);
  EXPECT_EQ(EvaluateLaw(Law::kStep, 0.5).s, 1.0);
}

TEST(LawsTest, KnownInteriorValues) {
  // tau = 1/4: smoothstep 3/16 - 2/64 = 5/32; minimum-jerk 10/64 - 15/256 + 6/1024 = 53/512.
  EXPECT_NEAR(EvaluateLaw(Law::kLinear, 0.25).s, 0.25, kRoundoff);
  EXPECT_NEAR(EvaluateLaw(Law::kSmoothstep, 0.25).s, 5.0 / 32.0, kRoundoff);
  EXPECT_NEAR(EvaluateLaw(Law::kMinimumJerk, 0.25).s, 53.0 / 512.0, kRoundoff);
  EXPECT_NEAR(EvaluateLaw(Law::kSmoothstep, 0.25).ds, 6.0 * 0.25 * 0.75, kRoundoff);
  EXPECT_NEAR(EvaluateLaw(Law::kMinimumJerk, 0.25).ds, 30.0 * 0.0625 * 0.5625, kRoundoff);
  EXPECT_NEAR(EvaluateLaw(Law::kMinimumJerk, 0.25).dds, 60.0 * 0.25 * 0.75 * 0.5, kRoundoff);
}

TEST(LawsTest, DerivativesMatchFiniteDifferences) {
  for (Law law : kContinuousLaws) {
    SCOPED_TRACE(ToString(law));
    for (double tau = 0.05; tau < 0.96; tau += 0.05) {
      const LawValue v = EvaluateLaw(law, tau);
      const LawValue vp = EvaluateLaw(law, tau + kFdStep);
      const LawValue vm = EvaluateLaw(law, tau - kFdStep);
      EXPECT_NEAR(v.ds, (vp.s - vm.s) / (2.0 * kFdStep), 3e-9)  // measured 7.2e-10
          << "tau = " << tau;
      EXPECT_NEAR(v.dds, (vp.ds - vm.ds) / (2.0 * kFdStep), kFdTolerance) << "tau = " << tau;
    }
  }
}

TEST(LawsTest, LinearRateJumpsAtBothEnds) {
  // Inside the stage the rate is 1; the neighbouring holds have rate 0: a breakpoint.
  EXPECT_EQ(EvaluateLaw(Law::kLinear, 0.0).ds, 1.0);
  EXPECT_EQ(EvaluateLaw(Law::kLinear, 1.0).ds, 1.0);
}

TEST(LawsTest, SmoothstepIsC1ButNotC2) {
  EXPECT_EQ(EvaluateLaw(Law::kSmoothstep, 0.0).ds, 0.0);
  EXPECT_EQ(EvaluateLaw(Law::kSmoothstep, 1.0).ds, 0.0);
  // The acceleration jumps from 0 (hold) to +-6: not C2.
  EXPECT_EQ(EvaluateLaw(Law::kSmoothstep, 0.0).dds, 6.0);
  EXPECT_EQ(EvaluateLaw(Law::kSmoothstep, 1.0).dds, -6.0);
}

TEST(LawsTest, MinimumJerkIsC2) {
  for (double tau : {0.0, 1.0}) {
    const LawValue v = EvaluateLaw(Law::kMinimumJerk, tau);
    EXPECT_EQ(v.ds, 0.0) << "tau = " << tau;
    EXPECT_EQ(v.dds, 0.0) << "tau = " << tau;
  }
  // Continuity, not just endpoint values: a small step away changes s'' by O(tau).
  EXPECT_LT(std::abs(EvaluateLaw(Law::kMinimumJerk, 1e-6).dds), 1e-4);
  EXPECT_LT(std::abs(EvaluateLaw(Law::kMinimumJerk, 1.0 - 1e-6).dds), 1e-4);
}

TEST(LawsTest, MonotoneWithinUnitIntervalAndSymmetric) {
  // s in [0, 1] and non-decreasing keeps tensor interpolation convex.
  for (Law law : kContinuousLaws) {
    SCOPED_TRACE(ToString(law));
    double prev = 0.0;
    for (int i = 0; i <= 1000; ++i) {
      const double tau = i / 1000.0;
      const LawValue v = EvaluateLaw(law, tau);
      EXPECT_GE(v.s, prev);
      EXPECT_LE(v.s, 1.0);
      EXPECT_GE(v.ds, 0.0);
      EXPECT_NEAR(v.s + EvaluateLaw(law, 1.0 - tau).s, 1.0, kRoundoff);
      prev = v.s;
    }
  }
}

TEST(LawsTest, ClampsTauToUnitInterval) {
  for (Law law : kAllLaws) {
    SCOPED_TRACE(ToString(law));
    EXPECT_EQ(EvaluateLaw(law, -0.5).s, 0.0);
    EXPECT_EQ(EvaluateLaw(law, 1.5).s, 1.0);
    EXPECT_EQ(EvaluateLaw(law, 1.5).ds, EvaluateLaw(law, 1.0).ds);
  }
}

TEST(LawsTest, NamesRoundTrip) {
  EXPECT_EQ(ToString(Law::kStep), "step");
  EXPECT_EQ(ToString(Law::kLinear), "linear");
  EXPECT_EQ(ToString(Law::kSmoothstep), "smoothstep");
  EXPECT_EQ(ToString(Law::kMinimumJerk), "minimum-jerk");
  for (Law law : kAllLaws) EXPECT_EQ(ParseLaw(ToString(law)), law);
}

TEST(LawsTest, ParseRejectsUnknownNameListingValidOnes) {
  try {
    ParseLaw("cubic");
    FAIL() << "accepted an unknown law";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'cubic'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("step, linear, smoothstep, minimum-jerk"), std::string::npos) << msg;
  }
  EXPECT_THROW(ParseLaw("Linear"), std::invalid_argument);  // names are case-sensitive
  EXPECT_THROW(ParseLaw(""), std::invalid_argument);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::schedule
