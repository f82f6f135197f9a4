// schedule::ValidateProfile on hinge profiles (`hinges:`, hinge_plan.h), built in C++: every
// cross-field rule, with messages naming the file, the key path as the file spells it
// (angles in degrees), the value and the rule. The same rules through YAML files:
// tests/io_yaml/hinge_profile_test.cpp and tests/io/bad_inputs/profile_hinges_*.yaml.

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "deploysim/math/number_format.h"
#include "deploysim/schedule/deployment_schedule.h"
#include "deploysim/schedule/profile.h"
#include "schedule_fixtures.h"

namespace deploysim::schedule {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using testing::HingedModel;
using testing::kPi;

constexpr double kDeg = kPi / 180.0;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A free hinge with a spring, damper, stops at [min_deg, max_deg] and a latch at 0 deg.
HingePlan FreeHinge(double min_deg, double max_deg) {
  HingePlan h;
  h.kind = HingePlan::Kind::kFree;
  h.drive.spring.stiffness = 1.0;
  h.drive.spring.rest_angle = 20.0 * kDeg;
  h.drive.damping = 0.3;
  h.drive.stops.min_angle = min_deg * kDeg;
  h.drive.stops.max_angle = max_deg * kDeg;
  h.drive.latch.enabled = true;
  h.drive.latch.angle = 0.0;
  return h;
}

/// The fixture's two-panel model (closed: wing_plus_x at -90 deg, wing_minus_x at 90 deg):
/// wing_plus_x released at 10 s, wing_minus_x 2 s after wing_plus_x latches.
Profile ValidHingeProfile() {
  Profile p;
  p.name = "spring";
  p.source = "h.yaml";
  p.model = HingedModel();
  p.mode = Mode::kGeometry;
  p.coupling = Coupling::kExact;
  p.initial.w_NB_B = math::Vec3(0.001, 0.5, 0.001);
  p.initial.configuration = "closed";
  p.start = 0.0;
  p.until = 100.0;
  HingePlan a = FreeHinge(-92.0, 2.0);
  a.drive.release.kind = Release::Kind::kAtTime;
  a.drive.release.time = 10.0;
  HingePlan b = FreeHinge(-2.0, 92.0);
  b.drive.spring.rest_angle = -20.0 * kDeg;
  b.drive.release.kind = Release::Kind::kAfterLatch;
  b.drive.release.panel = 0;
  b.drive.release.delay = 2.0;
  p.hinges = {a, b};
  return p;
}

/// ValidHingeProfile with a third panel (a copy of wing_minus_x) that is `plan`.
Profile ThreePanelProfile(const HingePlan& plan) {
  Profile p = ValidHingeProfile();
  model::Panel third = p.model.hinged.panels[1];
  third.name = "boom";
  p.model.hinged.panels.push_back(third);
  for (model::Configuration& c : p.model.configurations) {
    c.hinge_angles.conservativeResize(3);
    c.hinge_angles[2] = c.hinge_angles[1];
  }
  p.hinges.push_back(plan);
  return p;
}

HingeMove To(double angle_deg, Law law, double t_begin, double t_end) {
  HingeMove m;
  m.kind = HingeMove::Kind::kTo;
  m.angle = angle_deg * kDeg;
  m.law = law;
  m.t_begin = t_begin;
  m.t_end = t_end;
  return m;
}

HingeMove Rate(double rate_deg_s, double t_begin, double t_end) {
  HingeMove m;
  m.kind = HingeMove::Kind::kRate;
  m.rate = rate_deg_s * kDeg;
  m.t_begin = t_begin;
  m.t_end = t_end;
  return m;
}

/// ValidHingeProfile with wing_minus_x prescribed along `moves`.
Profile PrescribedProfile(std::vector<HingeMove> moves) {
  Profile p = ValidHingeProfile();
  p.hinges[1] = HingePlan();
  p.hinges[1].kind = HingePlan::Kind::kPrescribed;
  p.hinges[1].moves = std::move(moves);
  return p;
}

void ExpectRejected(const Profile& p, const std::string& expected) {
  try {
    ValidateProfile(p);
    ADD_FAILURE() << "accepted an invalid profile; expected: " << expected;
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(expected), std::string::npos)
        << "message: " << m << "\nexpected to contain: " << expected;
    EXPECT_EQ(m.rfind(p.source + ": ", 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

/// Applies `edit` to a copy of `base` and expects the message to contain `expected`.
void ExpectEditRejected(const Profile& base,
                        const std::function<void(Profile&)>& edit,
                        const std::string& expected) {
  Profile p = base;
  edit(p);
  ExpectRejected(p, expected);
}

const std::string kA = "h.yaml: hinges.wing_plus_x.free";
const std::string kB = "h.yaml: hinges.wing_minus_x.free";

TEST(HingeProfileValidationTest, AcceptsValidHingeProfiles) {
  const Profile p = ValidHingeProfile();
  ASSERT_TRUE(p.is_hinge_profile());
  EXPECT_NO_THROW(ValidateProfile(p));
  EXPECT_EQ(p.t_begin(), 0.0);
  EXPECT_EQ(p.t_end(), 100.0);
  // Every drive part at once; jam; a torque-speed motor driving towards negative angles.
  Profile q = p;
  FreeDrive& d = q.hinges[0].drive;
  d.spring.preload = -0.1;
  d.motor.kind = Motor::Kind::kTorqueSpeed;
  d.motor.stall_torque = -0.2;
  d.motor.no_load_speed = -30.0 * kDeg;
  d.friction.torque = 0.01;
  d.friction.regularization_speed = 0.5 * kDeg;
  d.stops.restitution = 1.0;
  d.latch.jam_fraction = 0.5;
  EXPECT_NO_THROW(ValidateProfile(q));
  // A constant motor of either sign; no friction with no regularization speed.
  q.hinges[0].drive.motor = Motor();
  q.hinges[0].drive.motor.kind = Motor::Kind::kConstant;
  q.hinges[0].drive.motor.torque = 0.0;
  q.hinges[0].drive.friction = Friction();
  EXPECT_NO_THROW(ValidateProfile(q));
  // Free hinges with nothing (moved by the spin only), and locked ones.
  q = p;
  q.hinges[0].drive = FreeDrive();
  q.hinges[1] = HingePlan();
  EXPECT_NO_THROW(ValidateProfile(q));
  // Prescribed moves that touch, start at the profile's start and end after the run.
  EXPECT_NO_THROW(ValidateProfile(
      PrescribedProfile({To(45.0, Law::kMinimumJerk, 0.0, 20.0), To(0.0, Law::kLinear, 20.0, 30.0),
                         Rate(3600.0, 30.0, 500.0)})));
}

TEST(HingeProfileValidationTest, RejectsWrongShape) {
  const Profile p = ValidHingeProfile();
  ExpectEditRejected(
      p, [](Profile& q) { q.stages = {testing::Hold("closed", 0.0, 10.0)}; },
      "h.yaml: stages: a profile has either stages (every panel through the stages' "
      "configurations) or hinges (a plan per panel), not both");
  ExpectEditRejected(
      p,
      [](Profile& q) {
        q.model = testing::TensorModel();
        q.model.source.clear();
      },
      "h.yaml: model: hinges need a hinged model (model 'three_tensors' is kind tensors)");
  ExpectEditRejected(
      p, [](Profile& q) { q.mode = Mode::kTensor; },
      "h.yaml: mode = tensor: a hinge profile runs in geometry mode");
  ExpectEditRejected(
      p, [](Profile& q) { q.coupling = Coupling::kQuasiRigid; },
      "h.yaml: coupling = quasi-rigid: a hinge profile runs with exact coupling");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges.pop_back(); },
      "h.yaml: hinges: 1 plans for 2 panels (one per panel, in the model's panel order)");
  ExpectEditRejected(
      p, [](Profile& q) { q.initial.configuration.clear(); },
      "h.yaml: initial.configuration: required key is missing");
  ExpectEditRejected(
      p, [](Profile& q) { q.initial.configuration = "folded"; },
      "h.yaml: initial.configuration = 'folded': no configuration of that name in model "
      "'smallsat' (valid: closed, half_open, open)");
  // The initial state's own rules hold as in stage profiles.
  ExpectEditRejected(
      p, [](Profile& q) { q.initial.w_NB_B = math::Vec3(0.0, kNaN, 0.0); },
      "h.yaml: initial.angular_velocity = [0, nan, 0]: must be finite");
  ExpectEditRejected(
      p, [](Profile& q) { q.output.dt = 0.0; }, "h.yaml: output.dt = 0: must be > 0");
  // A stage profile has no initial configuration (its first stage names it).
  Profile s =
      testing::MakeProfile(HingedModel(), Mode::kGeometry, Coupling::kExact, Law::kMinimumJerk);
  s.initial.configuration = "closed";
  ExpectRejected(s,
                 "p.yaml: initial.configuration = 'closed': only in hinge profiles (a stage "
                 "profile starts in the configuration of its first stage)");
}

TEST(HingeProfileValidationTest, RejectsBadRunTimes) {
  const Profile p = ValidHingeProfile();
  ExpectEditRejected(
      p, [](Profile& q) { q.until = 0.0; }, "h.yaml: until = 0: must be > start (0 s)");
  ExpectEditRejected(
      p, [](Profile& q) { q.start = kNaN; }, "h.yaml: start = nan: must be finite");
  ExpectEditRejected(
      p, [](Profile& q) { q.until = kInf; }, "h.yaml: until = inf: must be finite");
  // The stages' minimum duration applies to the run: 1 s at t = 1e9 s is rounding noise.
  ExpectEditRejected(
      p,
      [](Profile& q) {
        q.start = -1e9;
        q.until = -1e9 + 1.0;
        q.hinges[0].drive.release.time = -1e9;
      },
      "h.yaml: until = -999999999: the run lasts 1 s, less than the minimum 10 s = 1e-08 x "
      "max(|start|, |until|) (rule: minimum run duration)");
}

TEST(HingeProfileValidationTest, RejectsNonFiniteNumbersAnywhere) {
  const std::vector<std::pair<std::function<void(Profile&)>, std::string>> cases = {
      {[](Profile& q) { q.hinges[0].drive.spring.stiffness = kNaN; },
       kA + ".spring.stiffness = nan: must be finite"},
      {[](Profile& q) { q.hinges[0].drive.spring.rest_angle = kInf; },
       kA + ".spring.rest_angle_deg = inf: must be finite"},
      {[](Profile& q) { q.hinges[0].drive.spring.preload = -kInf; },
       kA + ".spring.preload = -inf: must be finite"},
      {[](Profile& q) { q.hinges[0].drive.damping = kNaN; },
       kA + ".damper.coefficient = nan: must be finite"},
      {[](Profile& q) {
         q.hinges[0].drive.motor.kind = Motor::Kind::kConstant;
         q.hinges[0].drive.motor.torque = kNaN;
       },
       kA + ".motor.torque = nan: must be finite"},
      {[](Profile& q) {
         q.hinges[0].drive.motor.kind = Motor::Kind::kTorqueSpeed;
         q.hinges[0].drive.motor.stall_torque = kInf;
         q.hinges[0].drive.motor.no_load_speed = 1.0;
       },
       kA + ".motor.stall_torque = inf: must be finite"},
      {[](Profile& q) {
         q.hinges[0].drive.motor.kind = Motor::Kind::kTorqueSpeed;
         q.hinges[0].drive.motor.stall_torque = 1.0;
         q.hinges[0].drive.motor.no_load_speed = kNaN;
       },
       kA + ".motor.no_load_speed_deg_s = nan: must be finite"},
      {[](Profile& q) { q.hinges[0].drive.friction.torque = kNaN; },
       kA + ".friction.torque = nan: must be finite"},
      {[](Profile& q) {
         q.hinges[0].drive.friction.torque = 0.1;
         q.hinges[0].drive.friction.regularization_speed = kInf;
       },
       kA + ".friction.regularization_speed_deg_s = inf: must be finite"},
      {[](Profile& q) { q.hinges[0].drive.stops.min_angle = kNaN; },
       kA + ".stops.min_deg = nan: must be finite (leave it out for no stop)"},
      {[](Profile& q) { q.hinges[0].drive.stops.min_angle = kInf; },
       kA + ".stops.min_deg = inf: must be finite"},
      {[](Profile& q) { q.hinges[0].drive.stops.max_angle = -kInf; },
       kA + ".stops.max_deg = -inf: must be finite"},
      {[](Profile& q) { q.hinges[0].drive.stops.restitution = kNaN; },
       kA + ".stops.restitution = nan: must be finite"},
      {[](Profile& q) { q.hinges[0].drive.latch.angle = kNaN; },
       kA + ".latch.angle_deg = nan: must be finite"},
      {[](Profile& q) { q.hinges[0].drive.latch.jam_fraction = kNaN; },
       kA + ".latch.jam_fraction = nan: must be finite"},
      {[](Profile& q) { q.hinges[0].drive.release.time = kInf; },
       kA + ".release.at = inf: must be finite"},
      {[](Profile& q) { q.hinges[1].drive.release.delay = kNaN; },
       kB + ".release.delay = nan: must be finite"},
  };
  for (const auto& [edit, expected] : cases) {
    SCOPED_TRACE(expected);
    ExpectEditRejected(ValidHingeProfile(), edit, expected);
  }
  const std::string m = "h.yaml: hinges.wing_minus_x.prescribed[0]";
  ExpectRejected(PrescribedProfile({To(kNaN, Law::kLinear, 0.0, 1.0)}),
                 m + ".to_deg = nan: must be finite");
  ExpectRejected(PrescribedProfile({Rate(kInf, 0.0, 1.0)}),
                 m + ".rate_deg_s = inf: must be finite");
  ExpectRejected(PrescribedProfile({Rate(1.0, kNaN, 1.0)}), m + ".start = nan: must be finite");
  ExpectRejected(PrescribedProfile({Rate(1.0, 0.0, kInf)}), m + ".until = inf: must be finite");
}

TEST(HingeProfileValidationTest, RejectsNegativeStiffnessDampingAndFriction) {
  const Profile p = ValidHingeProfile();
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.spring.stiffness = -0.5; },
      kA + ".spring.stiffness = -0.5: must be >= 0 [N m/rad]");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[1].drive.damping = -1e-3; },
      kB + ".damper.coefficient = -0.001: must be >= 0 [N m s/rad]");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.friction.torque = -0.01; },
      kA + ".friction.torque = -0.01: must be >= 0 [N m] (0: no friction)");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.friction.regularization_speed = -1.0 * kDeg; },
      kA + ".friction.regularization_speed_deg_s = -1: must be >= 0.01 deg/s");
  // Below the floor the regularized law is stiff: at 1e-6 deg/s a 600 s run did not
  // finish in a minute.
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.friction.regularization_speed = 1e-6 * kDeg; },
      kA + ".friction.regularization_speed_deg_s = 1e-06: must be >= 0.01 deg/s");
}

// Outside the accepted ranges (hinge_plan.h) a value describes no panel's hardware and the
// run's cost cannot be bounded: refused in one line naming the key, the value and the rule.
TEST(HingeProfileValidationTest, RefusesValuesOutsideTheAcceptedRanges) {
  const Profile p = ValidHingeProfile();
  const std::string rule = " (rule: accepted range of a free hinge)";
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.spring.rest_angle = 1e12 * kDeg; },
      kA + ".spring.rest_angle_deg = 1e+12: must be within +-3600 deg" + rule);
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.spring.stiffness = 2e9; },
      kA + ".spring.stiffness = 2e+09: must be within +-1e+09 N m/rad" + rule);
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[1].drive.damping = 1e10; },
      kB + ".damper.coefficient = 1e+10: must be within +-1e+09 N m s/rad" + rule);
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.spring.preload = -2e6; },
      kA + ".spring.preload = -2e+06: must be within +-1e+06 N m" + rule);
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.friction.torque = 5e6; },
      kA + ".friction.torque = 5e+06: must be within +-1e+06 N m" + rule);
  // The limits themselves are accepted.
  Profile ok = p;
  ok.hinges[0].drive.spring.stiffness = schedule::kMaxDriveStiffness;
  ok.hinges[0].drive.spring.rest_angle = schedule::kMaxDriveAngle;
  EXPECT_NO_THROW(ValidateProfile(ok));
}

TEST(HingeProfileValidationTest, RejectsMotorsThatDoNotDriveOneWay) {
  const Profile p = ValidHingeProfile();
  auto motor = [](double stall, double speed_deg_s) {
    return [stall, speed_deg_s](Profile& q) {
      q.hinges[0].drive.motor.kind = Motor::Kind::kTorqueSpeed;
      q.hinges[0].drive.motor.stall_torque = stall;
      q.hinges[0].drive.motor.no_load_speed = speed_deg_s * kDeg;
    };
  };
  ExpectEditRejected(p, motor(0.0, 30.0),
                     kA + ".motor.stall_torque = 0: must be non-zero [N m] (the torque at rest; "
                          "its sign is the direction the motor drives)");
  ExpectEditRejected(p, motor(0.2, 0.0), kA + ".motor.no_load_speed_deg_s = 0: must be non-zero");
  ExpectEditRejected(p, motor(0.2, -30.0),
                     kA + ".motor.no_load_speed_deg_s = -30: must have the sign of stall_torque "
                          "(0.2 N m)");
  ExpectEditRejected(p, motor(-0.2, 30.0),
                     kA + ".motor.no_load_speed_deg_s = 30: must have the sign of stall_torque "
                          "(-0.2 N m)");
}

TEST(HingeProfileValidationTest, StopsAndLatch) {
  const Profile p = ValidHingeProfile();
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.latch.angle = 3.0 * kDeg; },
      kA + ".latch.angle_deg = 3: the latch angle must lie within the stops [-92, 2] deg");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.latch.angle = -92.5 * kDeg; },
      kA + ".latch.angle_deg = -92.5: the latch angle must lie within the stops [-92, 2] deg");
  ExpectEditRejected(
      p,
      [](Profile& q) {
        q.hinges[1].drive.latch.angle = q.model.configurations[0].hinge_angles[1];  // pi/2
      },
      kB + ".latch.angle_deg = 90: the latch angle must differ from the hinge's initial angle "
           "(90 deg in configuration 'closed'): the hinge would latch before it moves");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.stops.min_angle = -80.0 * kDeg; },
      kA + ".stops.min_deg = -80: the hinge's initial angle (-90 deg in configuration "
           "'closed') must lie within the stops [-80, 2] deg");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[1].drive.stops.max_angle = 80.0 * kDeg; },
      kB + ".stops.max_deg = 80: the hinge's initial angle (90 deg in configuration 'closed') "
           "must lie within the stops [-2, 80] deg");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[1].drive.stops.max_angle = -2.0 * kDeg; },
      kB + ".stops.max_deg = -2: must be > min_deg (-2)");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.stops.restitution = 1.01; },
      kA + ".stops.restitution = 1.01: must be in [0, 1]");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.stops.restitution = -0.1; },
      kA + ".stops.restitution = -0.1: must be in [0, 1]");
  ExpectEditRejected(
      p,
      [](Profile& q) {
        q.hinges[0].drive.stops = Stops();
        q.hinges[0].drive.stops.restitution = 0.5;
      },
      kA + ".stops.restitution = 0.5: a restitution needs a stop (min_deg or max_deg) to "
           "rebound from");
  for (double jam : {1.0, -0.25, 1.5}) {
    ExpectEditRejected(
        p, [jam](Profile& q) { q.hinges[0].drive.latch.jam_fraction = jam; },
        ".latch.jam_fraction = " + math::FormatNumber(jam) + ": must be in (0, 1)");
  }
  ExpectEditRejected(
      p,
      [](Profile& q) {
        q.hinges[0].drive.latch.enabled = false;
        q.hinges[0].drive.latch.jam_fraction = 0.5;
        q.hinges[1].drive.release = Release();
      },
      kA + ".latch.jam_fraction = 0.5: a jam needs a latch");
  // Inclusive bounds: a latch on a stop, an initial angle on a stop; one-sided stops.
  Profile q = p;
  q.hinges[0].drive.latch.angle = 2.0 * kDeg;
  q.hinges[0].drive.stops.min_angle = -90.0 * kDeg;
  EXPECT_NO_THROW(ValidateProfile(q));
  q.hinges[0].drive.stops.min_angle = -kInf;
  q.hinges[1].drive.stops.max_angle = kInf;
  EXPECT_NO_THROW(ValidateProfile(q));
}

TEST(HingeProfileValidationTest, ReleaseRules) {
  const Profile p = ValidHingeProfile();
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.release.time = -1.0; },
      kA + ".release.at = -1: must be >= start (0 s; leave release out for a hinge free from "
           "the start)");
  EXPECT_NO_THROW(ValidateProfile([&] {
    Profile q = p;
    q.hinges[0].drive.release.time = 0.0;  // at the start
    return q;
  }()));
  for (int bad : {-1, 2}) {
    ExpectEditRejected(
        p, [bad](Profile& q) { q.hinges[1].drive.release.panel = bad; },
        kB + ".release.after_latch = " + std::to_string(bad) +
            ": no such panel (the model has 2 panels)");
  }
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[1].drive.release.panel = 1; },
      kB + ".release.after_latch = wing_minus_x: a hinge cannot wait for its own latch");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0] = HingePlan(); },
      kB + ".release.after_latch = wing_plus_x: panel 'wing_plus_x' is locked: a release waits "
           "for a free hinge with a latch");
  ExpectEditRejected(
      p,
      [](Profile& q) {
        q.hinges[0] = HingePlan();
        q.hinges[0].kind = HingePlan::Kind::kPrescribed;
        q.hinges[0].moves = {To(0.0, Law::kLinear, 0.0, 10.0)};
      },
      "panel 'wing_plus_x' is prescribed: a release waits for a free hinge with a latch");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[0].drive.latch = Latch(); },
      kB + ".release.after_latch = wing_plus_x: panel 'wing_plus_x' has no latch: it never "
           "latches, so this hinge would never be released");
  ExpectEditRejected(
      p, [](Profile& q) { q.hinges[1].drive.release.delay = -0.5; },
      kB + ".release.delay = -0.5: must be >= 0 [s]");
  // Cycles: two panels waiting on each other, and three.
  ExpectEditRejected(
      p,
      [](Profile& q) {
        q.hinges[0].drive.release.kind = Release::Kind::kAfterLatch;
        q.hinges[0].drive.release.panel = 1;
      },
      kA + ".release.after_latch = wing_minus_x: the releases wait on each other in a cycle of 2 "
           "panels (back to 'wing_plus_x'): none of them would ever be released");
  HingePlan boom = FreeHinge(-2.0, 92.0);
  boom.drive.release.kind = Release::Kind::kAfterLatch;
  boom.drive.release.panel = 1;  // boom after wing_minus_x after wing_plus_x
  Profile chain = ThreePanelProfile(boom);
  EXPECT_NO_THROW(ValidateProfile(chain));
  chain.hinges[0].drive.release.kind = Release::Kind::kAfterLatch;
  chain.hinges[0].drive.release.panel = 2;  // ... after boom: a cycle of 3
  ExpectRejected(chain,
                 kA + ".release.after_latch = boom: the releases wait on each other in a cycle "
                      "of 3 panels (back to 'wing_plus_x')");
}

TEST(HingeProfileValidationTest, PrescribedMoves) {
  const std::string m = "h.yaml: hinges.wing_minus_x.prescribed";
  ExpectRejected(PrescribedProfile({}), m + ": at least one move is required");
  ExpectRejected(PrescribedProfile({To(0.0, Law::kStep, 10.0, 20.0)}),
                 m + "[0].law = step: the step law is not allowed for a hinge");
  ExpectRejected(PrescribedProfile({Rate(10.0, 10.0, 20.0), To(0.0, Law::kLinear, 30.0, 30.0)}),
                 m + "[1].until = 30: a move ends after it starts (start = 30 s)");
  ExpectRejected(
      PrescribedProfile({To(45.0, Law::kSmoothstep, 10.0, 20.0), Rate(10.0, 19.0, 40.0)}),
      m + "[1].start = 19: the moves of a hinge are in time order and do not overlap (the "
          "previous move ends at 20 s)");
  ExpectRejected(PrescribedProfile({To(45.0, Law::kSmoothstep, -1.0, 20.0)}),
                 m + "[0].start = -1: a move starts at or after the profile's start (0 s)");
  // Window ends are breakpoints: the stages' minimum duration (1e-8 of the time scale).
  ExpectRejected(PrescribedProfile({To(45.0, Law::kLinear, 10.0, 10.0 + 1e-7)}),
                 m + "[0].until = 10.0000001: the move lasts");
  ExpectRejected(PrescribedProfile({To(45.0, Law::kLinear, 10.0, 10.0 + 1e-7)}),
                 "less than the minimum 1e-06 s = 1e-08 x the time scale (100 s) (rule: "
                 "minimum move duration)");
  EXPECT_NO_THROW(ValidateProfile(PrescribedProfile({To(45.0, Law::kLinear, 10.0, 10.0 + 2e-6)})));
}

TEST(HingeProfileValidationTest, DeploymentScheduleRefusesHingeProfiles) {
  // A DeploymentSchedule follows stages; a hinge profile has none (its stages_.front()
  // was read out of range before this check).
  try {
    const DeploymentSchedule schedule(ValidHingeProfile());
    ADD_FAILURE() << "a DeploymentSchedule was built from a hinge profile";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("h.yaml: hinges: a DeploymentSchedule follows the "
                                          "stages of a stage profile; a hinge profile has none",
                                          0),
              0u)
        << e.what();
  }
}

TEST(HingeProfileValidationTest, NamesTheProfileWhenItHasNoSource) {
  Profile p = ValidHingeProfile();
  p.source.clear();
  p.hinges[0].drive.damping = -1.0;
  try {
    ValidateProfile(p);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "profile 'spring': hinges.wing_plus_x.free.damper.coefficient = -1: must be >= "
                 "0 [N m s/rad]");
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::schedule
