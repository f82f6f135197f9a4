// Issue 4, acceptance 4: spring-driven deployment. Simbody swings the smallsat's wings
// open with torsional springs and dampers and latches them on stiff stops; the reduced
// model replays the recorded hinge history with exact coupling and must agree to 1e-7
// relative in H_B.

#include "deploysim/crosscheck/spring_deployment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include "deploysim/io/yaml_loader.h"

namespace deploysim::crosscheck {
namespace {

constexpr double kReplayTolerance = 1e-7;  // issue 4 acceptance 4, relative in H_B
constexpr double kHorizon = 120.0;         // [s] deployment in ~2 s, then 118 s latched
constexpr double kLatchTolerance = 1e-3;   // [rad] final angle vs the open angle

// The smallsat released from its stowed configuration at t = 0 (one hold stage: the
// profile only fixes the model, the initial spin and the horizon).
schedule::Profile Release() {
  schedule::Profile p = io::LoadProfile(std::string(DEPLOYSIM_SOURCE_DIR) +
                                        "/deployment_profiles/smallsat_three_stage.yaml");
  p.name = "smallsat_spring_release";
  p.stages = {schedule::Stage{"release", "closed", "closed", schedule::Law::kStep, 0.0, kHorizon}};
  return p;
}

SpringDeploymentOptions Drive() {
  SpringDeploymentOptions o;
  o.drive.open = "open";
  o.drive.stiffness = 0.5;          // N m/rad: 90 deg in ~2 s for a 1.3 kg m^2 wing
  o.drive.overtravel = 0.1745;      // rad (10 deg): the spring keeps pressing on the stop
  o.drive.damping = 0.3;            // N m s/rad
  o.drive.stop_stiffness = 1000.0;  // N m/rad
  o.drive.stop_dissipation = 0.5;   // s/rad
  o.accuracy = 1e-12;
  return o;
}

TEST(SpringDeploymentTest, ReplayAgreesWithSimbody) {
  const SpringDeploymentResult r = RunSpringDeployment(Release(), Drive());
  std::cout << FormatSpringDeploymentTable(r);
  EXPECT_LE(r.difference.max_H_B_relative, kReplayTolerance);
  EXPECT_LE(r.max_flip_difference, 1e-6);
  // The wings really deployed and latched: both reached the stop early, ended on it.
  ASSERT_EQ(r.latch_times.size(), 2u);
  const Eigen::VectorXd open = r.profile.model.configuration("open").hinge_angles;
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_TRUE(std::isfinite(r.latch_times[k]));
    EXPECT_LT(r.latch_times[k], 10.0);
    EXPECT_NEAR(r.simbody.trajectory.hinge_angles.back()[static_cast<Eigen::Index>(k)],
                open[static_cast<Eigen::Index>(k)], kLatchTolerance);
  }
  // The deployment moved the momentum in the body (a hub counter-rotation about y): the
  // comparison is not of two constant vectors.
  const math::Vec3 H0 = r.simbody.trajectory.H_B.front();
  double moved = 0.0;
  for (const math::Vec3& H : r.simbody.trajectory.H_B) moved = std::max(moved, (H - H0).norm());
  EXPECT_GT(moved, 0.01 * H0.norm());
  EXPECT_LE(r.simbody.max_momentum_drift, 1e-10);
  EXPECT_LE(r.replay_max_h_N_drift, 1e-12);
  RecordProperty("max_H_B_relative", std::to_string(r.difference.max_H_B_relative));
  RecordProperty("max_attitude_rad", std::to_string(r.difference.max_attitude));
  RecordProperty("knots", std::to_string(r.simbody.history.size()));
}

TEST(SpringDeploymentTest, RejectsBadDrives) {
  const schedule::Profile p = Release();
  SpringDeploymentOptions o = Drive();
  o.t_end = 5.0;
  o.drive.stiffness = -1.0;
  EXPECT_THROW(RunSpringDeployment(p, o), std::invalid_argument);
  o = Drive();
  o.t_end = 5.0;
  o.drive.open = "wide_open";  // no such configuration
  EXPECT_THROW(RunSpringDeployment(p, o), std::invalid_argument);
}

}  // namespace
}  // namespace deploysim::crosscheck
