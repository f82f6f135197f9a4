// The initial spin in the units analysts use (deg/s, rpm, a spin axis with a nutation
// angle), read back to the same state as rad/s; and the warnings a legal but almost
// certainly unmeant profile gets (schedule/profile_warnings.h), each one triggered by one
// change to the main job's profile, none on the shipped profiles.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/io/yaml_fields.h"
#include "deploysim/io/yaml_reader.h"
#include "deploysim/schedule/initial_spin.h"
#include "deploysim/schedule/profile_warnings.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

constexpr double kDeg = M_PI / 180.0;
constexpr double kRpm = 2.0 * M_PI / 60.0;

std::string Source(const std::string& rel) { return std::string(DEPLOYSIM_SOURCE_DIR) + "/" + rel; }

std::string FileText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const std::string kMainJob = "deployment_profiles/smallsat_spring_deploy.yaml";
const std::string kMainJobSpin = "  angular_velocity: [0.0091, 0.5235988, 0.0091]\n";

/// The main job's profile with `from` replaced by `to` (which must occur once).
schedule::Profile MainJobWith(const std::string& from, const std::string& to) {
  std::string text = FileText(Source(kMainJob));
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << from;
  text.replace(at, from.size(), to);
  return ReadProfileText(text, "main.yaml", Source("deployment_profiles"));
}

std::vector<std::string> WarningsWith(const std::string& from, const std::string& to) {
  return schedule::ProfileWarnings(MainJobWith(from, to));
}

// ---- units ----

TEST(InitialUnitsTest, DegreesPerSecondAndRpmReadAsRadiansPerSecond) {
  // 5 rpm = 30 deg/s = pi/6 rad/s about y, 0.3 rpm = 1.8 deg/s = pi/100 rad/s about x.
  const math::Vec3 w =
      *MainJobWith(kMainJobSpin,
                   "  angular_velocity: [0.031415926535897934, 0.5235987755982988, 0]\n")
           .initial.w_NB_B;
  const schedule::Profile deg =
      MainJobWith(kMainJobSpin, "  angular_velocity_deg_s: [1.8, 30, 0]\n");
  const schedule::Profile rpm = MainJobWith(kMainJobSpin, "  angular_velocity_rpm: [0.3, 5, 0]\n");
  EXPECT_LT((*deg.initial.w_NB_B - w).norm(), 1e-16);
  EXPECT_LT((*rpm.initial.w_NB_B - w).norm(), 1e-16);
  EXPECT_FALSE(deg.initial.H_B);
  EXPECT_FALSE(rpm.initial.spin);
}

TEST(InitialUnitsTest, SpinAxisRateAndNutationGiveThatState) {
  for (const std::string rate : {"rate_rpm: 5", "rate_deg_s: 30", "rate: 0.5235987755982988"}) {
    const schedule::Profile p =
        MainJobWith(kMainJobSpin, "  spin: {axis: y, " + rate + ", nutation_deg: 1.4}\n");
    ASSERT_TRUE(p.initial.H_B) << rate;
    ASSERT_TRUE(p.initial.spin) << rate;
    EXPECT_FALSE(p.initial.w_NB_B);
    const dynamics::InertiaSample s0 = schedule::InitialInertia(p);
    const math::Vec3 H = *p.initial.H_B;
    const math::Vec3 w = s0.J_inv_B * (H - s0.h_rel_B);
    EXPECT_NEAR(w.y(), 5.0 * kRpm, 1e-14) << rate;
    EXPECT_NEAR(std::acos(H.normalized().y()), 1.4 * kDeg, 1e-12) << rate;
  }
}

TEST(InitialUnitsTest, SpinWithoutNutationIsAPureSpinAboutAPrincipalAxis) {
  const schedule::Profile p = MainJobWith(kMainJobSpin, "  spin: {axis: -y, rate_rpm: 2}\n");
  const dynamics::InertiaSample s0 = schedule::InitialInertia(p);
  const math::Vec3 w = s0.J_inv_B * (*p.initial.H_B - s0.h_rel_B);
  EXPECT_NEAR(w.y(), -2.0 * kRpm, 1e-15);
  EXPECT_NEAR(std::hypot(w.x(), w.z()), 0.0, 1e-15);
}

TEST(InitialUnitsTest, AStageProfileTakesASpinToo) {
  std::string text = FileText(Source("deployment_profiles/smallsat_three_stage.yaml"));
  const std::size_t at = text.find("  angular_velocity:");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, text.find('\n', at) - at,
               "  spin: {axis: [0, 1, 0], rate_rpm: 5, nutation_deg: 2}");
  const schedule::Profile p = ReadProfileText(text, "stage.yaml", Source("deployment_profiles"));
  const dynamics::InertiaSample s0 = schedule::InitialInertia(p);
  const math::Vec3 w = s0.J_inv_B * (*p.initial.H_B - s0.h_rel_B);
  EXPECT_NEAR(w.y(), 5.0 * kRpm, 1e-14);
  EXPECT_NEAR(std::acos(p.initial.H_B->normalized().y()), 2.0 * kDeg, 1e-12);
}

std::string ErrorWith(const std::string& to) {
  try {
    MainJobWith(kMainJobSpin, to);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(InitialUnitsTest, BadSpinsAreRefusedByKey) {
  EXPECT_EQ(ErrorWith("  spin: {axis: y, rate_rpm: -5}\n"),
            "main.yaml: initial.spin.rate_rpm = -5: must be > 0 (the axis gives the direction)");
  EXPECT_NE(ErrorWith("  spin: {axis: y, rate_rpm: 5, nutation_deg: 95}\n")
                .find("initial.spin.nutation_deg = 95: must be in [0, 90) deg"),
            std::string::npos);
  EXPECT_NE(
      ErrorWith("  spin: {axis: w, rate_rpm: 5}\n").find("initial.spin.axis = w: unknown axis"),
      std::string::npos);
  EXPECT_NE(ErrorWith("  spin: {axis: [0, 0, 0], rate_rpm: 5}\n").find("must be a non-zero vector"),
            std::string::npos);
  EXPECT_NE(ErrorWith("  spin: {axis: y, rate_rpm: 5, rate: 1}\n")
                .find("exactly one of rate_rpm, rate_deg_s, rate is required (rate_rpm, rate are "
                      "given)"),
            std::string::npos);
  EXPECT_NE(ErrorWith(kMainJobSpin + "  angular_velocity_rpm: [0, 5, 0]\n")
                .find("exactly one of angular_velocity, angular_velocity_deg_s, "
                      "angular_velocity_rpm, angular_momentum, spin is required"),
            std::string::npos);
}

// ---- warnings ----

TEST(ProfileWarningsTest, ShippedProfilesHaveNone) {
  for (const auto& entry : std::filesystem::directory_iterator(Source("deployment_profiles"))) {
    const schedule::Profile p = ReadProfile(entry.path().string());
    EXPECT_EQ(schedule::ProfileWarnings(p), std::vector<std::string>{}) << entry.path();
  }
}

/// The one warning of the main job changed by from -> to; it names `key`.
void ExpectOneWarning(const std::string& from,
                      const std::string& to,
                      const std::string& key,
                      const std::string& says) {
  const std::vector<std::string> w = WarningsWith(from, to);
  ASSERT_EQ(w.size(), 1u) << to;
  EXPECT_EQ(w[0].rfind("main.yaml: " + key, 0), 0u) << w[0];
  EXPECT_NE(w[0].find(says), std::string::npos) << w[0];
}

TEST(ProfileWarningsTest, EachLegalButUnmeantInputGetsOneLine) {
  // 1. A release after the run's end; the panel waiting on it is never released either.
  const std::vector<std::string> late = WarningsWith("release: {at: 60}", "release: {at: 900}");
  ASSERT_EQ(late.size(), 2u);
  EXPECT_EQ(late[0],
            "main.yaml: hinges.wing_plus_x.free.release.at = 900: at or after the run's end "
            "(until = 600 s): the panel is never released in this run");
  EXPECT_NE(late[1].find("hinges.wing_minus_x.free.release.after_latch = wing_plus_x: released "
                         "at the earliest at 902 s"),
            std::string::npos);
  // 2. A release delay that ends after the run.
  ExpectOneWarning("delay: 2.0}", "delay: 560}", "hinges.wing_minus_x.free.release.after_latch",
                   "at the earliest at 620 s");
  // 3. A spring that rests short of the latch (it stops near 52 deg, never latches).
  ExpectOneWarning(
      "      spring: {stiffness: 0.2, rest_angle_deg: -30}         # N m/rad; preload 0",
      "      spring: {stiffness: 0.2, rest_angle_deg: 60}",
      "hinges.wing_plus_x.free.spring.rest_angle_deg = 60",
      "comes to rest at 60 deg, short of the latch at 0 deg (starting at 90 deg)");
  // 4. A spring pushing the panel the other way.
  ExpectOneWarning(
      "      spring: {stiffness: 0.2, rest_angle_deg: -30}         # N m/rad; preload 0",
      "      spring: {stiffness: 0.2, rest_angle_deg: 120}",
      "hinges.wing_plus_x.free.spring.rest_angle_deg = 120", "short of the latch");
  // 5. 30 rad/s typed where 30 deg/s was meant.
  ExpectOneWarning(kMainJobSpin, "  angular_velocity: [0, 30, 0]\n", "initial.angular_velocity",
                   "286.5 rpm");
  ExpectOneWarning(kMainJobSpin, "  spin: {axis: y, rate: 30}\n", "initial.spin.rate",
                   "faster than spacecraft spin");
  ExpectOneWarning(kMainJobSpin, "  spin: {axis: y, rate_deg_s: 1800}\n", "initial.spin.rate",
                   "faster than spacecraft spin");
  // In rpm the unit is chosen on purpose: Explorer 1 spun at 750 rpm.
  EXPECT_EQ(WarningsWith(kMainJobSpin, "  spin: {axis: y, rate_rpm: 750}\n"),
            std::vector<std::string>{});
  // 6. Friction that holds the panel at release.
  ExpectOneWarning("      friction: {torque: 0.02, regularization_speed_deg_s: 1.0}   # N m",
                   "      friction: {torque: 0.5}", "hinges.wing_plus_x.free.friction.torque = 0.5",
                   "the panel may never start to move");
  // 7. Nothing drives the panel to its latch.
  ExpectOneWarning(
      "      spring: {stiffness: 0.2, rest_angle_deg: -30}         # N m/rad; preload 0\n", "",
      "hinges.wing_plus_x.free.latch.angle_deg = 0", "nothing drives the panel");
  // 8. A motor that drives the panel away from its latch.
  ExpectOneWarning(
      "      spring: {stiffness: 0.2, rest_angle_deg: -30}         # N m/rad; preload 0",
      "      motor: {torque: 0.05}", "hinges.wing_plus_x.free.motor.torque = 0.05",
      "away from its latch");
  // 9. A run sampled too coarsely to show the deployment.
  ExpectOneWarning("  dt: 0.1", "  dt: 10", "output.dt = 10", "sampled fewer than 100 times");
}

TEST(ProfileWarningsTest, PrescribedMovesPastTheEnd) {
  const std::string free_minus_x =
      "    free:\n"
      "      release: {after_latch: wing_plus_x, delay: 2.0}       # s after wing_plus_x latches\n"
      "      spring: {stiffness: 0.2, rest_angle_deg: -30}\n"
      "      damper: {coefficient: 1.0}\n"
      "      friction: {torque: 0.02, regularization_speed_deg_s: 1.0}\n"
      "      stops: {min_deg: -2, max_deg: 92, restitution: 0.3}\n"
      "      latch: {angle_deg: 0}\n";
  // 10. A move to an angle cut short by the run's end; 11. a move after it.
  const std::vector<std::string> w =
      WarningsWith(free_minus_x,
                   "    prescribed:\n"
                   "      - {to_deg: 30, law: minimum-jerk, start: 590, until: 620}\n"
                   "      - {to_deg: 0, law: minimum-jerk, start: 650, until: 700}\n");
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0],
            "main.yaml: hinges.wing_minus_x.prescribed[0].until = 620: after the run's end "
            "(until = 600 s): the run stops the panel part way through its move");
  EXPECT_EQ(w[1],
            "main.yaml: hinges.wing_minus_x.prescribed[1].start = 650: at or after the run's "
            "end (until = 600 s): the move never happens in this run");
  // A rotor's rate move may run past the end (dual_spin_rotor.yaml): no warning.
  EXPECT_TRUE(WarningsWith(free_minus_x,
                           "    prescribed:\n"
                           "      - {rate_deg_s: 10, start: 100, until: 700}\n")
                  .empty());
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
