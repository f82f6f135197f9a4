// Hinge profiles (`hinges:`, docs/file_formats.md "Hinge profiles") read by io_yaml's
// ReadProfile: every key read back into schedule::HingePlan, degrees converted, panel
// names resolved to indices, the defaults, the shipped example, and a few messages word
// for word (the bad-input corpus, tests/io/bad_inputs/profile_hinges_*.yaml, has one file
// per rule).

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "deploysim/io/yaml_fields.h"
#include "deploysim/io/yaml_reader.h"
#include "deploysim/math/quaternion.h"
#include "temp_dir_test.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using schedule::HingeMove;
using schedule::HingePlan;
using schedule::Motor;
using schedule::Release;

constexpr double kDeg = M_PI / 180.0;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Four panels: two wings, a rotor (hinge through its CoM) and a boom.
const char* const kModel = R"(name: four_panels
kind: hinged
hub:
  mass: 85.0
  box: [0.6, 1.0, 0.8]
panels:
  - {name: wing_plus_x, mass: 6.0, box: [0.8, 1.0, 0.02], hinge_point: [0.3, 0, 0.4], hinge_axis: [0, 1, 0], com_offset: [0.4, 0, 0.01]}
  - {name: wing_minus_x, mass: 6.0, box: [0.8, 1.0, 0.02], hinge_point: [-0.3, 0, -0.4], hinge_axis: [0, 1, 0], com_offset: [-0.4, 0, -0.01]}
  - {name: boom, mass: 1.0, box: [0.02, 0.02, 1.0], hinge_point: [0, 0.5, 0], hinge_axis: [1, 0, 0], com_offset: [0, 0, 0.5]}
  - {name: rotor, mass: 2.0, box: [0.2, 0.05, 0.2], hinge_point: [0, -0.5, 0], hinge_axis: [0, 1, 0], com_offset: [0, 0, 0]}
configurations:
  closed: {hinge_angles_deg: [90, 90, 0, 0]}
  open: {hinge_angles_deg: [0, 0, 0, 0]}
)";

// Every key of the schema.
const char* const kEveryKey = R"(name: every_key
description: "every key of a hinge profile"
model: four.yaml
mode: geometry
coupling: exact
initial:
  configuration: closed
  attitude_wxyz: [2, 0, 0, 0]
  angular_momentum: [0.1, 8.0, 0.1]
start: 5
until: 600
hinges:
  wing_plus_x:
    free:
      release: {at: 60}
      spring: {stiffness: 0.6, rest_angle_deg: -20, preload: 0.05}
      damper: {coefficient: 0.5}
      motor: {stall_torque: -0.2, no_load_speed_deg_s: -30}
      friction: {torque: 0.01, regularization_speed_deg_s: 0.5}
      stops: {min_deg: -5, max_deg: 95, restitution: 0.3}
      latch: {angle_deg: 0, jam_fraction: 0.8}
  rotor:
    prescribed:
      - {to_deg: 30, law: smoothstep, start: 60, until: 80}
      - {rate_deg_s: 3600, start: 100, until: 700}
  wing_minus_x:
    free:
      release: {after_latch: wing_plus_x, delay: 2.5}
      motor: {torque: -0.05}
      latch: {angle_deg: 0}
  boom:
    locked: true
integrator: {method: rkmk-rkf78, rtol: 1.0e-11}
output: {dt: 0.5, csv: true}
)";

class HingeProfileTest : public testing::TempDirTest {
 protected:
  /// Writes the model and `profile` (as hinges.yaml); returns the profile's path.
  std::string WriteProfile(const std::string& profile) {
    Write("four.yaml", kModel);
    return Write("hinges.yaml", profile);
  }

  /// The message of ReadProfile(path) ("" if it loads).
  static std::string ErrorOf(const std::string& path) {
    try {
      (void)ReadProfile(path);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  }

  /// kEveryKey with `from` replaced by `to` (which must occur once).
  static std::string Edited(const std::string& from, const std::string& to) {
    return EditedText(kEveryKey, from, to);
  }
  /// `text` with `from` replaced by `to` (which must occur once).
  static std::string EditedText(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    EXPECT_EQ(text.find(from, at + 1), std::string::npos) << from << " occurs twice";
    return text.replace(at, from.size(), to);
  }
};

TEST_F(HingeProfileTest, ReadsEveryKeyBackFieldByField) {
  const std::string path = WriteProfile(kEveryKey);
  const schedule::Profile p = ReadProfile(path);
  EXPECT_EQ(p.name, "every_key");
  EXPECT_EQ(p.description, "every key of a hinge profile");
  EXPECT_EQ(p.source, path);
  EXPECT_EQ(p.text, kEveryKey);
  EXPECT_EQ(p.model.name, "four_panels");
  EXPECT_TRUE(p.is_hinge_profile());
  EXPECT_TRUE(p.stages.empty());
  EXPECT_EQ(p.mode, schedule::Mode::kGeometry);
  EXPECT_EQ(p.coupling, schedule::Coupling::kExact);
  EXPECT_EQ(p.initial.configuration, "closed");
  EXPECT_EQ(math::ToWxyz(p.initial.q_NB), math::Vec4(1, 0, 0, 0)) << "normalized on load";
  ASSERT_TRUE(p.initial.H_B.has_value());
  EXPECT_EQ(*p.initial.H_B, math::Vec3(0.1, 8.0, 0.1));
  EXPECT_FALSE(p.initial.w_NB_B.has_value());
  EXPECT_EQ(p.start, 5.0);
  EXPECT_EQ(p.until, 600.0);
  EXPECT_EQ(p.t_begin(), 5.0);
  EXPECT_EQ(p.t_end(), 600.0);
  EXPECT_EQ(p.integrator.method, "rkmk-rkf78");
  EXPECT_EQ(p.integrator.rtol, 1.0e-11);
  EXPECT_EQ(p.output.dt, 0.5);
  EXPECT_TRUE(p.output.csv);

  // One plan per panel, in the model's panel order (not the file's).
  ASSERT_EQ(p.hinges.size(), 4u);

  const HingePlan& a = p.hinges[0];  // wing_plus_x: every key of a free drive
  ASSERT_EQ(a.kind, HingePlan::Kind::kFree);
  EXPECT_TRUE(a.moves.empty());
  const schedule::FreeDrive& d = a.drive;
  EXPECT_EQ(d.release.kind, Release::Kind::kAtTime);
  EXPECT_EQ(d.release.time, 60.0);
  EXPECT_EQ(d.spring.stiffness, 0.6);
  EXPECT_DOUBLE_EQ(d.spring.rest_angle, -20.0 * kDeg);
  EXPECT_EQ(d.spring.preload, 0.05);
  EXPECT_EQ(d.damping, 0.5);
  EXPECT_EQ(d.motor.kind, Motor::Kind::kTorqueSpeed);
  EXPECT_EQ(d.motor.stall_torque, -0.2);
  EXPECT_DOUBLE_EQ(d.motor.no_load_speed, -30.0 * kDeg) << "deg/s -> rad/s";
  EXPECT_EQ(d.friction.torque, 0.01);
  EXPECT_DOUBLE_EQ(d.friction.regularization_speed, 0.5 * kDeg);
  EXPECT_DOUBLE_EQ(d.stops.min_angle, -5.0 * kDeg);
  EXPECT_DOUBLE_EQ(d.stops.max_angle, 95.0 * kDeg);
  EXPECT_EQ(d.stops.restitution, 0.3);
  EXPECT_TRUE(d.latch.enabled);
  EXPECT_EQ(d.latch.angle, 0.0);
  EXPECT_EQ(d.latch.jam_fraction, 0.8);

  const HingePlan& b = p.hinges[1];  // wing_minus_x: released by wing_plus_x's latch
  ASSERT_EQ(b.kind, HingePlan::Kind::kFree);
  EXPECT_EQ(b.drive.release.kind, Release::Kind::kAfterLatch);
  EXPECT_EQ(b.drive.release.panel, 0) << "the panel name resolves to its index";
  EXPECT_EQ(b.drive.release.delay, 2.5);
  EXPECT_EQ(b.drive.motor.kind, Motor::Kind::kConstant);
  EXPECT_EQ(b.drive.motor.torque, -0.05);
  EXPECT_TRUE(b.drive.latch.enabled);
  EXPECT_EQ(b.drive.latch.jam_fraction, 0.0) << "no jam unless given";

  EXPECT_EQ(p.hinges[2].kind, HingePlan::Kind::kLocked);  // boom

  const HingePlan& r = p.hinges[3];  // rotor
  ASSERT_EQ(r.kind, HingePlan::Kind::kPrescribed);
  ASSERT_EQ(r.moves.size(), 2u);
  EXPECT_EQ(r.moves[0].kind, HingeMove::Kind::kTo);
  EXPECT_DOUBLE_EQ(r.moves[0].angle, 30.0 * kDeg);
  EXPECT_EQ(r.moves[0].law, schedule::Law::kSmoothstep);
  EXPECT_EQ(r.moves[0].t_begin, 60.0);
  EXPECT_EQ(r.moves[0].t_end, 80.0);
  EXPECT_EQ(r.moves[1].kind, HingeMove::Kind::kRate);
  EXPECT_DOUBLE_EQ(r.moves[1].rate, 3600.0 * kDeg) << "10 turns a second, in rad/s";
  EXPECT_EQ(r.moves[1].t_begin, 100.0);
  EXPECT_EQ(r.moves[1].t_end, 700.0) << "a move may end after the run";
}

TEST_F(HingeProfileTest, DegreesUseTheReadersOneFactor) {
  // The same factor as hinge_angles_deg of the model: a latch written at a configuration's
  // angle compares equal to it (the latch-angle != initial-angle rule relies on it).
  const schedule::Profile p = ReadProfile(WriteProfile(kEveryKey));
  EXPECT_EQ(p.hinges[0].drive.stops.max_angle, 95.0 * yaml::kRadiansPerDegree);
  EXPECT_EQ(p.model.configurations[0].hinge_angles[0], 90.0 * yaml::kRadiansPerDegree);
  EXPECT_DOUBLE_EQ(yaml::kRadiansPerDegree, M_PI / 180.0);
}

TEST_F(HingeProfileTest, DefaultsAndPanelsLeftOut) {
  const schedule::Profile p = ReadProfile(WriteProfile(R"(name: defaults
model: four.yaml
initial:
  configuration: open
  angular_velocity: [0, 0.5, 0]
until: 10
hinges:
  rotor:
    free: {}
)"));
  EXPECT_EQ(p.mode, schedule::Mode::kGeometry) << "the only mode of a hinge profile";
  EXPECT_EQ(p.coupling, schedule::Coupling::kExact) << "the only coupling of a hinge profile";
  EXPECT_EQ(p.start, 0.0);
  EXPECT_EQ(math::ToWxyz(p.initial.q_NB), math::Vec4(1, 0, 0, 0));
  ASSERT_EQ(p.hinges.size(), 4u);
  for (int k : {0, 1, 2}) {
    EXPECT_EQ(p.hinges[k].kind, HingePlan::Kind::kLocked) << "panel " << k << " is not listed";
  }
  ASSERT_EQ(p.hinges[3].kind, HingePlan::Kind::kFree);
  // A free hinge with nothing: moved only by the spin, free from the start, no stops.
  const schedule::FreeDrive& d = p.hinges[3].drive;
  EXPECT_EQ(d.release.kind, Release::Kind::kAtStart);
  EXPECT_EQ(d.spring.stiffness, 0.0);
  EXPECT_EQ(d.damping, 0.0);
  EXPECT_EQ(d.motor.kind, Motor::Kind::kNone);
  EXPECT_EQ(d.friction.torque, 0.0);
  EXPECT_EQ(d.stops.min_angle, -kInf);
  EXPECT_EQ(d.stops.max_angle, kInf);
  EXPECT_FALSE(d.stops.any());
  EXPECT_FALSE(d.latch.enabled);

  // One stop only; an empty hinges mapping locks every panel.
  std::string text = Edited("      stops: {min_deg: -5, max_deg: 95, restitution: 0.3}\n",
                            "      stops: {max_deg: 95}\n");
  const schedule::Profile one = ReadProfile(WriteProfile(text));
  EXPECT_EQ(one.hinges[0].drive.stops.min_angle, -kInf);
  EXPECT_DOUBLE_EQ(one.hinges[0].drive.stops.max_angle, 95.0 * kDeg);
  EXPECT_EQ(one.hinges[0].drive.stops.restitution, 0.0);
  const schedule::Profile none = ReadProfile(WriteProfile(R"(name: all_locked
model: four.yaml
initial: {configuration: open, angular_velocity: [0, 0.5, 0]}
until: 10
hinges: {}
)"));
  ASSERT_EQ(none.hinges.size(), 4u);
  for (const HingePlan& h : none.hinges) EXPECT_EQ(h.kind, HingePlan::Kind::kLocked);
  EXPECT_TRUE(none.is_hinge_profile());
}

// initial.hinge_rates_deg_s: one rate per panel, in deg/s; non-zero only for a hinge
// free from the start.
TEST_F(HingeProfileTest, InitialHingeRates) {
  const std::string text = R"(name: moving
model: four.yaml
initial:
  configuration: open
  angular_velocity: [0, 0.5, 0]
  hinge_rates_deg_s: [0, 0, 0, 3600]
until: 10
hinges:
  rotor:
    free: {}
)";
  const schedule::Profile p = ReadProfile(WriteProfile(text));
  ASSERT_EQ(p.initial.hinge_rates.size(), 4);
  EXPECT_DOUBLE_EQ(p.initial.hinge_rates[3], 3600 * kDeg);
  EXPECT_EQ(p.initial.hinge_rates[0], 0.0);
  std::string path = WriteProfile(EditedText(text, "[0, 0, 0, 3600]", "[0, 0, 3600]"));
  EXPECT_EQ(ErrorOf(path), path +
                               ": initial.hinge_rates_deg_s: 3 rates for 4 panels (one per "
                               "panel, in the model's order)");
  path = WriteProfile(EditedText(text, "[0, 0, 0, 3600]", "[10, 0, 0, 3600]"));
  EXPECT_EQ(ErrorOf(path),
            path +
                ": initial.hinge_rates_deg_s[0] (wing_plus_x) = 10: only a free hinge "
                "released at the start may move at `start` (a prescribed hinge's rate comes "
                "from its moves; a locked or held one is at rest)");
  path = WriteProfile(EditedText(text, "    free: {}", "    free: {release: {at: 5}}"));
  EXPECT_NE(ErrorOf(path).find("initial.hinge_rates_deg_s[3] (rotor) = 3600: only a free hinge"),
            std::string::npos)
      << ErrorOf(path);
}

TEST_F(HingeProfileTest, StageProfilesHaveNoHinges) {
  const schedule::Profile p = ReadProfile(WriteProfile(R"(name: stages
model: four.yaml
mode: geometry
coupling: exact
initial: {angular_velocity: [0, 0.5, 0]}
stages:
  - {hold: closed, until: 10}
  - {to: open, law: minimum-jerk, until: 20}
)"));
  EXPECT_FALSE(p.is_hinge_profile());
  EXPECT_TRUE(p.hinges.empty());
  EXPECT_TRUE(p.initial.configuration.empty());
  EXPECT_EQ(p.start, 0.0);
  EXPECT_EQ(p.until, 0.0);
  EXPECT_EQ(p.t_end(), 20.0);
}

TEST_F(HingeProfileTest, ShippedSpringDeploymentLoadsAndValidates) {
  const std::string path =
      std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/smallsat_spring_deploy.yaml";
  const schedule::Profile p = ReadProfile(path);  // ValidateProfile included
  EXPECT_NO_THROW(schedule::ValidateProfile(p));
  EXPECT_EQ(p.model.name, "smallsat");
  EXPECT_EQ(p.initial.configuration, "closed");
  EXPECT_EQ(p.t_begin(), 0.0);
  EXPECT_EQ(p.t_end(), 600.0);
  ASSERT_EQ(p.hinges.size(), 2u);
  for (const HingePlan& h : p.hinges) {
    ASSERT_EQ(h.kind, HingePlan::Kind::kFree);
    EXPECT_EQ(h.drive.spring.stiffness, 0.2);
    EXPECT_DOUBLE_EQ(h.drive.spring.rest_angle, -30.0 * kDeg);
    EXPECT_EQ(h.drive.damping, 1.0);
    EXPECT_TRUE(h.drive.latch.enabled);
    EXPECT_EQ(h.drive.latch.angle, 0.0);
    EXPECT_DOUBLE_EQ(h.drive.stops.min_angle, -2.0 * kDeg);
    EXPECT_DOUBLE_EQ(h.drive.stops.max_angle, 92.0 * kDeg);
  }
  EXPECT_EQ(p.hinges[0].drive.release.kind, Release::Kind::kAtTime);
  EXPECT_EQ(p.hinges[0].drive.release.time, 60.0);
  EXPECT_EQ(p.hinges[1].drive.release.kind, Release::Kind::kAfterLatch);
  EXPECT_EQ(p.hinges[1].drive.release.panel, 0);
  EXPECT_EQ(p.hinges[1].drive.release.delay, 2.0);
}

// Whole messages: file, key path as in the file, value (degrees as written), rule.
TEST_F(HingeProfileTest, MessagesNameFileKeyValueAndRule) {
  std::string path = WriteProfile(Edited("latch: {angle_deg: 0, jam_fraction: 0.8}",
                                         "latch: {angle_deg: 95.5, jam_fraction: 0.8}"));
  EXPECT_EQ(ErrorOf(path), path +
                               ": hinges.wing_plus_x.free.latch.angle_deg = 95.5: the latch "
                               "angle must lie within the stops [-5, 95] deg");
  path = WriteProfile(Edited("damper: {coefficient: 0.5}", "damper: {coefficient: -0.5}"));
  EXPECT_EQ(ErrorOf(path),
            path + ": hinges.wing_plus_x.free.damper.coefficient = -0.5: must be >= 0 [N m s/rad]");
  path = WriteProfile(Edited("spring: {stiffness: 0.6,", "spring: {stiffness: -0.6,"));
  EXPECT_EQ(ErrorOf(path),
            path + ": hinges.wing_plus_x.free.spring.stiffness = -0.6: must be >= 0 [N m/rad]");
  path = WriteProfile(Edited("after_latch: wing_plus_x", "after_latch: wing_plus"));
  EXPECT_EQ(ErrorOf(path), path +
                               ": hinges.wing_minus_x.free.release.after_latch = wing_plus: no "
                               "panel of that name in model 'four_panels' (valid: wing_plus_x, "
                               "wing_minus_x, boom, rotor)");
  path = WriteProfile(Edited("spring: {stiffness: 0.6, rest_angle_deg: -20,",
                             "spring: {stiffness: 0.6, rest_angle_deg: .nan,"));
  EXPECT_EQ(ErrorOf(path),
            path + ": hinges.wing_plus_x.free.spring.rest_angle_deg = .nan: must be finite");
  path = WriteProfile(Edited("  boom:\n", "  boom_arm:\n"));
  EXPECT_EQ(ErrorOf(path), path +
                               ": hinges.boom_arm = {locked: true}: no panel of that name in "
                               "model 'four_panels' (valid: wing_plus_x, wing_minus_x, boom, "
                               "rotor)");
  path = WriteProfile(Edited("      - {rate_deg_s: 3600, start: 100, until: 700}\n",
                             "      - {rate_deg_s: 3600, start: 70, until: 700}\n"));
  EXPECT_EQ(ErrorOf(path), path +
                               ": hinges.rotor.prescribed[1].start = 70: the moves of a hinge are "
                               "in time order and do not overlap (the previous move ends at 80 "
                               "s)");
  path = WriteProfile(Edited("initial:\n", "stages:\n  - {hold: closed, until: 10}\ninitial:\n"));
  EXPECT_EQ(ErrorOf(path).rfind(path + ": hinges = {wing_plus_x: {free: ", 0), 0u) << ErrorOf(path);
  EXPECT_NE(ErrorOf(path).find(": a profile has either stages (every panel through the stages' "
                               "configurations) or hinges (a plan per panel), not both"),
            std::string::npos);
}

TEST_F(HingeProfileTest, EveryMessageIsOneLineInvalidArgument) {
  // A sample of edits across the reader and ValidateProfile.
  const std::pair<const char*, const char*> edits[] = {
      {"until: 600", "until: 5"},
      {"configuration: closed", "configuration: [closed]"},
      {"restitution: 0.3", "restitution: -0.1"},
      {"jam_fraction: 0.8", "jam_fraction: 0"},
      {"delay: 2.5", "delay: yes"},
      {"law: smoothstep", "law: step"},
      {"locked: true", "locked: 1"},
      {"no_load_speed_deg_s: -30", "no_load_speed_deg_s: 30"},
      {"mode: geometry", "mode: [geometry]"},
  };
  for (const auto& [from, to] : edits) {
    SCOPED_TRACE(to);
    const std::string path = WriteProfile(Edited(from, to));
    if (std::string(to) == "jam_fraction: 0") {
      EXPECT_EQ(ErrorOf(path), "") << "jam_fraction 0 is no jam";
      continue;
    }
    try {
      (void)ReadProfile(path);
      ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind(path + ": ", 0), 0u) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
