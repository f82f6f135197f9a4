// The cross-check's verdict (crosscheck::Judge): which differences make the reduced
// model and Simbody disagree, and the first rule broken as the reason.

#include <gtest/gtest.h>

#include <limits>

#include "deploysim/crosscheck/crosscheck.h"

namespace deploysim::crosscheck {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

TrajectoryDifference Small() {
  TrajectoryDifference d;
  d.max_H_B_relative = 1e-9;
  d.max_w = 1e-9;
  d.w_scale = 0.5;
  return d;
}

TEST(CrosscheckVerdict, AgreesWithinTheTolerance) {
  const CrosscheckVerdict v = Judge(Small(), 1e-6, true, 1e-8, 100.0, 1e-4);
  EXPECT_TRUE(v.agree) << v.reason;
  EXPECT_NE(FormatVerdict(v).find("verdict: agree"), std::string::npos);
}

TEST(CrosscheckVerdict, AMissingEventOrFlipIsADisagreement) {
  const CrosscheckVerdict events = Judge(Small(), 1e-6, false, 0.0, 100.0, 1e-4);
  EXPECT_FALSE(events.agree);
  EXPECT_NE(events.reason.find("hinge events differ"), std::string::npos);
  const CrosscheckVerdict flips =
      Judge(Small(), std::numeric_limits<double>::infinity(), true, 0.0, 100.0, 1e-4);
  EXPECT_FALSE(flips.agree);
  EXPECT_NE(flips.reason.find("flip counts differ"), std::string::npos);
  EXPECT_NE(FormatVerdict(flips).find("verdict: DISAGREE: the flip counts differ"),
            std::string::npos);
}

TEST(CrosscheckVerdict, EachDifferenceBeyondTheToleranceIsADisagreement) {
  TrajectoryDifference h = Small();
  h.max_H_B_relative = 2e-4;
  EXPECT_NE(Judge(h, 0.0, true, 0.0, 100.0, 1e-4).reason.find("H_B differs"), std::string::npos);
  TrajectoryDifference w = Small();
  w.max_w = 1e-4;  // 2e-4 of w_scale
  EXPECT_NE(Judge(w, 0.0, true, 0.0, 100.0, 1e-4).reason.find("w_NB_B differs"), std::string::npos);
  // Times: relative to the run's length (100 s: 1e-2 s).
  EXPECT_TRUE(Judge(Small(), 0.009, true, 0.009, 100.0, 1e-4).agree);
  EXPECT_NE(Judge(Small(), 0.02, true, 0.0, 100.0, 1e-4).reason.find("flip time"),
            std::string::npos);
  EXPECT_NE(Judge(Small(), 0.0, true, 0.02, 100.0, 1e-4).reason.find("event time"),
            std::string::npos);
  // A NaN difference is not an agreement.
  TrajectoryDifference nan = Small();
  nan.max_H_B_relative = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(Judge(nan, 0.0, true, 0.0, 100.0, 1e-4).agree);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::crosscheck
