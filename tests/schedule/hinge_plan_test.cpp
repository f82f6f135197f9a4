// Hinge plans (schedule/hinge_plan.h): the kinds' names, which the profile reader takes
// as the keys of a hinge's plan, and the documented values of the plan constants.

#include "deploysim/schedule/hinge_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace deploysim::schedule {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

TEST(HingePlanTest, KindsAreNamedAsTheProfileKeys) {
  EXPECT_EQ(ToString(HingePlan::Kind::kLocked), "locked");
  EXPECT_EQ(ToString(HingePlan::Kind::kPrescribed), "prescribed");
  EXPECT_EQ(ToString(HingePlan::Kind::kFree), "free");
  // A default plan is locked, its drive released at the start with no latch.
  const HingePlan h;
  EXPECT_EQ(h.kind, HingePlan::Kind::kLocked);
  EXPECT_EQ(h.drive.release.kind, Release::Kind::kAtStart);
  EXPECT_FALSE(h.drive.latch.enabled);
  EXPECT_EQ(h.drive.latch.jam_fraction, 0.0);
}

// The constants are what their comments say, in the units the files use.
TEST(HingePlanTest, ConstantsHaveTheirDocumentedValues) {
  const double deg = M_PI / 180.0;
  // 10 turns either way.
  EXPECT_NEAR(kMaxDriveAngle, 10.0 * 2.0 * M_PI, 4e-15);
  EXPECT_EQ(kMaxDriveAngleDeg, 3600.0);
  // 1000 turns/s.
  EXPECT_NEAR(kMaxDriveSpeed, 1000.0 * 2.0 * M_PI, 1e-12);
  // 0.01 deg/s.
  EXPECT_NEAR(kMinRegularizationSpeed, 0.01 * deg, 1e-19);
  // kRestSpeed: 0.0006 deg/s to the digit given, 10 um/s at the tip of a 1 m panel, and
  // 17 impacts at e = 0.5 from 1 rad/s.
  EXPECT_NEAR(kRestSpeed / deg, 0.0006, 0.00005);
  EXPECT_NEAR(kRestSpeed * 1.0, 10e-6, 1e-20);
  EXPECT_EQ(std::lround(std::log(kRestSpeed / 1.0) / std::log(0.5)), 17);
  EXPECT_EQ(kContactTime, 1e-3);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::schedule
