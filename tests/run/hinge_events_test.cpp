// The hinge event record (run/hinge_events.h): the kinds' names and their parser, the
// event table's columns (names in file order, values out and back in), and the deployment
// faults read off hand-built event lists: jam, never latched, rests short of the latch,
// never released, and their precedence.

#include "deploysim/run/hinge_events.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "run/hinge_fixtures.h"

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using Fault = analysis::DeploymentFault;
using Kind = HingeEvent::Kind;

TEST(HingeEventsTest, KindNamesRoundTripThroughTheParser) {
  const std::vector<std::string> names = {"release", "latch",    "jam",   "stop",
                                          "rest",    "lift-off", "stick", "slip"};
  ASSERT_EQ(kHingeEventKinds.size(), names.size());
  std::set<std::string> seen;
  for (std::size_t i = 0; i < kHingeEventKinds.size(); ++i) {
    const Kind k = kHingeEventKinds[i];
    EXPECT_EQ(static_cast<std::size_t>(k), i);  // declaration order
    EXPECT_EQ(ToString(k), names[i]);
    EXPECT_EQ(ParseHingeEventKind(ToString(k)), k);
    seen.insert(ToString(k));
  }
  EXPECT_EQ(seen.size(), names.size());
}

// The parser takes the names exactly and says which ones there are.
TEST(HingeEventsTest, AnUnknownKindIsRefusedWithTheValidNames) {
  for (const std::string bad : {"latched", "Latch", "", "lift_off", " stop"}) {
    try {
      ParseHingeEventKind(bad);
      ADD_FAILURE() << "'" << bad << "' accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()),
                "'" + bad +
                    "' is not a hinge event kind (release, latch, jam, stop, rest, lift-off, "
                    "stick, slip)");
    }
  }
}

// The table's standard columns, in file order, give each member of an event and read it
// back into a blank one; the text columns give the panel's name and the kind's.
TEST(HingeEventsTest, TableColumnsGiveAndTakeEveryMember) {
  std::vector<std::string> names;
  for (const HingeEventColumn& c : HingeEventTable::Columns()) names.push_back(c.name);
  const std::vector<std::string> standard = {
      "time",    "panel",    "panel_name",        "kind",      "angle", "rate_before", "rate_after",
      "impulse", "w_jump_B", "energy_dissipated", "drive_work"};
  ASSERT_GE(names.size(), standard.size());
  names.resize(standard.size());  // a test elsewhere in the process may have extended it
  EXPECT_EQ(names, standard);

  HingeEvent e;
  e.kind = Kind::kJam;
  e.t = 12.5;
  e.panel = 1;
  e.angle = 0.3;
  e.rate_before = -0.7;
  e.rate_after = 0.0;
  e.impulse = 2.25;
  e.w_jump_B = math::Vec3(1e-3, -2e-3, 4e-3);
  e.energy_dissipated = 0.125;
  e.drive_work = 0.5;
  const std::vector<std::string> panels = {"wing_plus_x", "wing_minus_x"};
  HingeEvent back;
  for (std::size_t i = 0; i < standard.size(); ++i) {
    const HingeEventColumn& c = HingeEventTable::Columns()[i];
    if (c.type == HingeEventColumn::Type::kText) {
      const std::string v = c.text(e, panels);
      if (c.name == "kind") {
        EXPECT_EQ(v, "jam");
      }
      if (c.name == "panel_name") {
        EXPECT_EQ(v, "wing_minus_x");
      }
      if (c.set_text) c.set_text(back, v);
    } else {
      EXPECT_EQ(c.width(), c.type == HingeEventColumn::Type::kVector3 ? 3 : 1) << c.name;
      double v[3] = {NAN, NAN, NAN};
      c.number(e, v);
      ASSERT_TRUE(c.set_number) << c.name;
      c.set_number(back, v);
    }
    // Only drive_work, added later, has a value for files that lack it.
    if (c.name == "drive_work") {
      EXPECT_EQ(c.missing, 0.0);
    } else {
      EXPECT_TRUE(std::isnan(c.missing)) << c.name;
    }
  }
  EXPECT_EQ(back.kind, e.kind);
  EXPECT_EQ(back.t, e.t);
  EXPECT_EQ(back.panel, e.panel);
  EXPECT_EQ(back.angle, e.angle);
  EXPECT_EQ(back.rate_before, e.rate_before);
  EXPECT_EQ(back.rate_after, e.rate_after);
  EXPECT_EQ(back.impulse, e.impulse);
  EXPECT_EQ(back.w_jump_B, e.w_jump_B);
  EXPECT_EQ(back.energy_dissipated, e.energy_dissipated);
  EXPECT_EQ(back.drive_work, e.drive_work);
  // A column of an existing name is refused.
  HingeEventColumn dup;
  dup.name = "impulse";
  EXPECT_THROW(HingeEventTable::Extend(dup), std::logic_error);
}

/// A free hinge with a latch at `latch_deg`, released as given.
schedule::HingePlan Latching(double latch_deg, schedule::Release release = {}) {
  schedule::HingePlan h = testing::SpringHinge(1.0, 0.0);
  h.drive.latch.enabled = true;
  h.drive.latch.angle = latch_deg * testing::kDeg;
  h.drive.release = release;
  return h;
}

schedule::Release AtTime(double t) {
  schedule::Release r;
  r.kind = schedule::Release::Kind::kAtTime;
  r.time = t;
  return r;
}

schedule::Release AfterLatch(int panel) {
  schedule::Release r;
  r.kind = schedule::Release::Kind::kAfterLatch;
  r.panel = panel;
  r.delay = 1.0;
  return r;
}

HingeEvent Event(Kind kind, int panel, double t, double angle = 0.0) {
  HingeEvent e;
  e.kind = kind;
  e.panel = panel;
  e.t = t;
  e.angle = angle;
  return e;
}

// Both wings released and latched: no fault; the events of one panel do not count for the
// other.
TEST(HingeEventsTest, LatchedWingsHaveNoFault) {
  const schedule::Profile p = testing::SmallsatHingeProfile(Latching(0.0), Latching(5.0), 100.0);
  EXPECT_TRUE(DeploymentFaults(p,
                               {Event(Kind::kRelease, 0, 0.0), Event(Kind::kRelease, 1, 0.0),
                                Event(Kind::kStop, 0, 3.0), Event(Kind::kLatch, 0, 4.0),
                                Event(Kind::kLatch, 1, 4.5)},
                               100.0)
                  .empty());
  const std::vector<Fault> f = DeploymentFaults(
      p,
      {Event(Kind::kRelease, 0, 0.0), Event(Kind::kRelease, 1, 0.0), Event(Kind::kLatch, 0, 4.0)},
      100.0);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].panel, 1);
  EXPECT_EQ(f[0].panel_name, "wing_minus_x");
  EXPECT_EQ(f[0].kind, Fault::Kind::kNeverLatched);
  EXPECT_TRUE(std::isnan(f[0].t));
  EXPECT_TRUE(std::isnan(f[0].angle));
  EXPECT_EQ(f[0].latch_angle, 5.0 * testing::kDeg);
  EXPECT_EQ(ToString(f[0].kind), "never latched");
}

// A jam: where and when it happened, and the latch it did not reach; it outranks a rest
// and a missing latch.
TEST(HingeEventsTest, AJamIsReportedWhereItHappened) {
  const schedule::Profile p = testing::SmallsatHingeProfile(Latching(0.0), Latching(0.0), 100.0);
  const std::vector<Fault> f =
      DeploymentFaults(p,
                       {Event(Kind::kRelease, 0, 0.0), Event(Kind::kRelease, 1, 0.0),
                        Event(Kind::kRest, 0, 8.0, 0.5), Event(Kind::kJam, 0, 12.5, 0.3),
                        Event(Kind::kLatch, 1, 6.0)},
                       100.0);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].kind, Fault::Kind::kJam);
  EXPECT_EQ(f[0].panel, 0);
  EXPECT_EQ(f[0].panel_name, "wing_plus_x");
  EXPECT_EQ(f[0].t, 12.5);
  EXPECT_EQ(f[0].angle, 0.3);
  EXPECT_EQ(f[0].latch_angle, 0.0);
  EXPECT_EQ(ToString(f[0].kind), "jam");
}

// Released, never latched, at rest on a stop: rests short of the latch, at the rest's
// time and angle.
TEST(HingeEventsTest, APanelRestingOnAStopRestsShortOfItsLatch) {
  const schedule::Profile p = testing::SmallsatHingeProfile(Latching(0.0), Latching(0.0), 100.0);
  const std::vector<Fault> f = DeploymentFaults(
      p,
      {Event(Kind::kRelease, 0, 0.0), Event(Kind::kRelease, 1, 0.0), Event(Kind::kLatch, 0, 5.0),
       Event(Kind::kStop, 1, 7.0, 0.2), Event(Kind::kRest, 1, 20.0, 0.2)},
      100.0);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].kind, Fault::Kind::kRestsShort);
  EXPECT_EQ(f[0].panel, 1);
  EXPECT_EQ(f[0].t, 20.0);
  EXPECT_EQ(f[0].angle, 0.2);
  EXPECT_EQ(ToString(f[0].kind), "rests short of latch");
}

// A release at a time is a fault only if that time falls inside the run; a release after
// a latch that never came is one always; a fault of its own outranks a jam.
TEST(HingeEventsTest, AReleaseThatWasDueButNeverCameIsReported) {
  const schedule::Profile p = testing::SmallsatHingeProfile(Latching(0.0, AtTime(50.0)),
                                                            Latching(0.0, AfterLatch(0)), 100.0);
  // Run to 40 s: the release at 50 s is not due; panel 1 waits for a latch: never released.
  std::vector<Fault> f = DeploymentFaults(p, {}, 40.0);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].panel, 1);
  EXPECT_EQ(f[0].kind, Fault::Kind::kNeverReleased);
  EXPECT_TRUE(std::isnan(f[0].t));
  EXPECT_EQ(ToString(f[0].kind), "never released");
  // Run to 60 s: both due, neither released (a jam recorded against a never-released panel
  // does not hide that).
  f = DeploymentFaults(p, {Event(Kind::kJam, 0, 55.0, 0.1)}, 60.0);
  ASSERT_EQ(f.size(), 2u);
  EXPECT_EQ(f[0].panel, 0);
  EXPECT_EQ(f[0].kind, Fault::Kind::kNeverReleased);
  EXPECT_EQ(f[1].panel, 1);
  EXPECT_EQ(f[1].kind, Fault::Kind::kNeverReleased);
  // Released and latched at their times: none.
  EXPECT_TRUE(DeploymentFaults(p,
                               {Event(Kind::kRelease, 0, 50.0), Event(Kind::kLatch, 0, 52.0),
                                Event(Kind::kRelease, 1, 53.0), Event(Kind::kLatch, 1, 56.0)},
                               60.0)
                  .empty());
}

// Only free hinges with a latch can miss it; locked and prescribed hinges have no faults.
TEST(HingeEventsTest, HingesWithoutALatchOrNotFreeHaveNoFault) {
  schedule::HingePlan locked;
  locked.kind = schedule::HingePlan::Kind::kLocked;
  schedule::HingePlan prescribed;
  prescribed.kind = schedule::HingePlan::Kind::kPrescribed;
  const schedule::HingePlan spring = testing::SpringHinge(1.0, 0.0);  // no latch
  const schedule::Profile a = testing::SmallsatHingeProfile(locked, spring, 100.0);
  EXPECT_TRUE(DeploymentFaults(a, {Event(Kind::kRelease, 1, 0.0)}, 100.0).empty());
  const schedule::Profile b = testing::SmallsatHingeProfile(prescribed, spring, 100.0);
  EXPECT_TRUE(
      DeploymentFaults(b, {Event(Kind::kRelease, 1, 0.0), Event(Kind::kRest, 1, 9.0)}, 100.0)
          .empty());
  // A jam needs no latch to be reported.
  const std::vector<Fault> f =
      DeploymentFaults(b, {Event(Kind::kRelease, 1, 0.0), Event(Kind::kJam, 1, 3.0, 0.4)}, 100.0);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].kind, Fault::Kind::kJam);
  EXPECT_TRUE(std::isnan(f[0].latch_angle));
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
