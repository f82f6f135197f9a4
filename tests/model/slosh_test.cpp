#include "deploysim/model/slosh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "deploysim/model/mass_properties.h"

namespace deploysim::model {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Mat3;
using math::Vec3;

constexpr double kExact = 1e-14;  // relative: a few roundings

HingedBody HubBody() {
  HingedBody b;
  b.hub.body.mass = 400.0;
  b.hub.body.inertia_cm = Eigen::Vector3d(150, 160, 90).asDiagonal();
  b.hub.com_B = Vec3(0.01, -0.02, 0.3);
  return b;
}

/// A tank 0.8 m off the z axis along x: a 30 kg pendulum 0.2 m long, 50 kg rigid.
SloshSpec Tank() {
  SloshSpec s;
  s.name = "tank";
  s.pivot = Vec3(0.8, 0.0, 0.1);
  s.direction = Vec3(2.0, 0.0, 0.0);  // normalized on expansion
  s.axis = Vec3(0.0, 0.0, 3.0);       // the spin axis
  s.mass = 30.0;
  s.length = 0.2;
  s.fixed_mass = 50.0;
  s.fixed_point = Vec3(0.85, 0.0, 0.1);
  s.damping = 0.4;
  return s;
}

/// S(d) = |d|^2 I - d d^T.
Mat3 S(const Vec3& d) { return d.squaredNorm() * Mat3::Identity() - d * d.transpose(); }

TEST(Slosh, PendulumOnTwoHinges) {
  HingedBody body = HubBody();
  const Appendage app = AddSlosh(body, Tank(), "test");
  ASSERT_EQ(body.panels.size(), 2u);
  EXPECT_EQ(app.kind, Appendage::Kind::kSlosh);
  EXPECT_EQ(app.root, -1);
  EXPECT_EQ(app.name, "tank");
  EXPECT_EQ(app.hinges, (std::vector<int>{0, 1}));
  EXPECT_EQ(app.stiffness, (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(app.damping, (std::vector<double>{0.4, 0.4}));
  const Panel& link = body.panels[0];
  EXPECT_EQ(link.name, "tank_a");
  EXPECT_EQ(link.parent, -1);
  EXPECT_EQ(link.body.mass, 0.0);
  EXPECT_TRUE(link.body.inertia_cm.isZero(0.0));
  EXPECT_TRUE(link.com_offset_B.isZero(0.0));
  EXPECT_EQ(link.hinge_point_B, Vec3(0.8, 0.0, 0.1));
  EXPECT_EQ(link.hinge_axis_B, Vec3::UnitZ());  // the first hinge: in the plane of rotation
  const Panel& bob = body.panels[1];
  EXPECT_EQ(bob.name, "tank_b");
  EXPECT_EQ(bob.parent, 0);
  EXPECT_EQ(bob.body.mass, 30.0);
  EXPECT_TRUE(bob.body.inertia_cm.isZero(0.0));
  EXPECT_TRUE(bob.hinge_point_B.isZero(0.0));
  EXPECT_EQ(bob.com_offset_B, Vec3(0.2, 0.0, 0.0));
  // direction x axis = x x z = -y: a positive angle swings the bob towards +z (the spin axis).
  EXPECT_EQ(bob.hinge_axis_B, -Vec3::UnitY());
  EXPECT_NO_THROW((void)ValidatedHingedBody(body, "test"));
}

// The fixed mass: the composite's moment of inertia about B's origin is the hub's plus
// m0 S(p) (the parallel-axis theorem taken back to one point), mass and first moment add.
TEST(Slosh, FixedMassIsAddedToTheHubExactly) {
  const HingedBody before = HubBody();
  HingedBody body = before;
  (void)AddSlosh(body, Tank(), "test");
  const SloshSpec s = Tank();
  const Hub& h0 = before.hub;
  const Hub& h = body.hub;
  EXPECT_NEAR(h.body.mass, 450.0, kExact * 450.0);
  const Vec3 first_moment = h0.body.mass * h0.com_B + s.fixed_mass * s.fixed_point;
  EXPECT_LT((h.body.mass * h.com_B - first_moment).norm(), kExact * first_moment.norm());
  const Mat3 about_origin =
      h0.body.inertia_cm + h0.body.mass * S(h0.com_B) + s.fixed_mass * S(s.fixed_point);
  const Mat3 got = h.body.inertia_cm + h.body.mass * S(h.com_B);
  EXPECT_LT((got - about_origin).norm(), kExact * about_origin.norm());
  // And the whole system's mass properties: 480 kg, the bob at pivot + L1 x.
  const MassProperties mp = ComputeMassProperties(ValidatedHingedBody(body, "test"),
                                                  Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero());
  const Vec3 c = (first_moment + 30.0 * Vec3(1.0, 0.0, 0.1)) / 480.0;
  EXPECT_NEAR(mp.mass, 480.0, kExact * 480.0);
  EXPECT_LT((mp.com_B - c).norm(), kExact);
}

// On a panel the fixed point is given from the panel's origin (its hinge point), in its
// axes, as the panel's own com_offset.
TEST(Slosh, FixedMassOnAParentPanel) {
  HingedBody body = HubBody();
  Panel arm;
  arm.name = "arm";
  arm.body.mass = 10.0;
  arm.body.inertia_cm = Eigen::Vector3d(1, 2, 3).asDiagonal();
  arm.hinge_point_B = Vec3(0.5, 0.0, 0.0);
  arm.hinge_axis_B = Vec3::UnitY();
  arm.com_offset_B = Vec3(0.4, 0.0, 0.0);
  body.panels.push_back(arm);
  SloshSpec s = Tank();
  s.parent = 0;
  s.fixed_point = Vec3(0.6, 0.0, 0.1);
  (void)AddSlosh(body, s, "test");
  const Panel& p = body.panels[0];
  EXPECT_NEAR(p.body.mass, 60.0, kExact * 60.0);
  const Vec3 c = (10.0 * Vec3(0.4, 0, 0) + 50.0 * s.fixed_point) / 60.0;
  EXPECT_LT((p.com_offset_B - c).norm(), kExact);
  const Mat3 about_origin =
      arm.body.inertia_cm + 10.0 * S(arm.com_offset_B) + 50.0 * S(s.fixed_point);
  EXPECT_LT((p.body.inertia_cm + 60.0 * S(p.com_offset_B) - about_origin).norm(),
            kExact * about_origin.norm());
  EXPECT_EQ(body.panels[1].parent, 0);
  EXPECT_EQ(body.panels[2].parent, 1);
  EXPECT_NO_THROW((void)ValidatedHingedBody(body, "test"));
}

TEST(Slosh, DefaultAxisIsPerpendicularToTheDirection) {
  for (const Vec3& d : {Vec3(1, 1, 0), Vec3(0.3, 0.2, 0.9), Vec3(0, 0, -1)}) {
    HingedBody body = HubBody();
    SloshSpec s = Tank();
    s.direction = d;
    s.axis.setZero();
    (void)AddSlosh(body, s, "test");
    const Vec3 a = body.panels[0].hinge_axis_B;
    const Vec3 b = body.panels[1].hinge_axis_B;
    const Vec3 u = d.normalized();
    EXPECT_NEAR(a.norm(), 1.0, kExact);
    EXPECT_NEAR(b.norm(), 1.0, kExact);
    EXPECT_NEAR(a.dot(u), 0.0, kExact);
    EXPECT_NEAR(b.dot(u), 0.0, kExact);
    EXPECT_NEAR(a.dot(b), 0.0, kExact);
    EXPECT_LT((body.panels[1].com_offset_B - 0.2 * u).norm(), kExact);
  }
}

TEST(Slosh, PendulumFrequenciesInTheCentrifugalField) {
  // omega_in^2 = Omega^2 r / L, omega_out^2 = Omega^2 (r + L) / L.
  EXPECT_NEAR(SloshInPlaneFrequency(2.0, 1.5, 0.5), 2.0 * std::sqrt(3.0), kExact);
  EXPECT_NEAR(SloshOutOfPlaneFrequency(2.0, 1.5, 0.5), 4.0, kExact);
  // On the spin axis: no restoring in the plane, the spin rate out of it.
  EXPECT_EQ(SloshInPlaneFrequency(2.0, 0.0, 0.5), 0.0);
  EXPECT_NEAR(SloshOutOfPlaneFrequency(2.0, 0.0, 0.5), 2.0, kExact);
}

TEST(Slosh, DampingFromARatio) {
  SloshSpec s = Tank();
  s.damping.reset();
  s.damping_ratio = 0.05;
  s.spin_rate = 2.0;
  s.spin_radius = 0.6;
  s.mass = 10.0;
  s.length = 0.2;  // omega_out = 2 sqrt(0.8 / 0.2) = 4 rad/s
  HingedBody body = HubBody();
  const Appendage app = AddSlosh(body, s, "test");
  // c = 2 zeta omega_out m1 L1^2 = 2 0.05 4 10 0.04 = 0.16 N m s/rad.
  EXPECT_NEAR(app.damping[0], 0.16, kExact);
  EXPECT_NEAR(app.damping[1], 0.16, kExact);
  EXPECT_NEAR(SloshDamping(s), 0.16, kExact);
  s.damping_ratio = 0.0;
  EXPECT_EQ(SloshDamping(s), 0.0);
}

/// The message AddSlosh throws for `s` (empty if it does not throw).
std::string Refusal(const SloshSpec& s) {
  HingedBody body = HubBody();
  try {
    (void)AddSlosh(body, s, "m.yaml: appendages[0]");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(Slosh, RefusesBadSpecsNamingTheKey) {
  const auto with = [](auto change) {
    SloshSpec s = Tank();
    change(s);
    return Refusal(s);
  };
  EXPECT_EQ(Refusal(Tank()), "");
  EXPECT_EQ(with([](SloshSpec& s) { s.mass = 0.0; }),
            "m.yaml: appendages[0].mass = 0: must be > 0 [kg] (the pendulum's m1)");
  EXPECT_EQ(with([](SloshSpec& s) { s.length = -0.1; }),
            "m.yaml: appendages[0].length = -0.1: must be > 0 [m] (the pendulum's L1)");
  EXPECT_EQ(with([](SloshSpec& s) { s.fixed_mass = -1.0; }),
            "m.yaml: appendages[0].fixed_mass = -1: must be >= 0 [kg]");
  EXPECT_EQ(with([](SloshSpec& s) { s.damping = -0.5; }),
            "m.yaml: appendages[0].damping = -0.5: must be >= 0 [N m s/rad]");
  EXPECT_NE(with([](SloshSpec& s) { s.damping_ratio = 0.1; }).find("give exactly one of"),
            std::string::npos);
  EXPECT_NE(with([](SloshSpec& s) { s.damping.reset(); }).find("give exactly one of"),
            std::string::npos);
  EXPECT_EQ(with([](SloshSpec& s) { s.spin_rate = 1.0; }),
            "m.yaml: appendages[0].spin_rate: only with damping_ratio (it sets the frequency at "
            "which the ratio is turned into the damper)");
  const auto ratio = [](SloshSpec& s) {
    s.damping.reset();
    s.damping_ratio = 0.02;
    s.spin_rate = 1.0;
    s.spin_radius = 0.8;
  };
  EXPECT_EQ(with(ratio), "");
  EXPECT_EQ(with([&](SloshSpec& s) {
              ratio(s);
              s.damping_ratio = 1.0;
            }),
            "m.yaml: appendages[0].damping_ratio = 1: must be in [0, 1)");
  EXPECT_EQ(with([&](SloshSpec& s) {
              ratio(s);
              s.spin_rate.reset();
            }),
            "m.yaml: appendages[0].spin_rate: required with damping_ratio [rad/s]");
  EXPECT_EQ(with([&](SloshSpec& s) {
              ratio(s);
              s.spin_rate = 0.0;
            }),
            "m.yaml: appendages[0].spin_rate = 0: must be > 0 [rad/s]");
  EXPECT_NE(with([&](SloshSpec& s) {
              ratio(s);
              s.spin_radius.reset();
            }).find("spin_radius: required with damping_ratio"),
            std::string::npos);
  EXPECT_EQ(with([&](SloshSpec& s) {
              ratio(s);
              s.spin_radius = -1.0;
            }),
            "m.yaml: appendages[0].spin_radius = -1: must be >= 0 [m]");
  EXPECT_EQ(with([](SloshSpec& s) { s.axis = Vec3(1, 0, 1); }),
            "m.yaml: appendages[0].axis: must be finite, non-zero and perpendicular to direction");
  EXPECT_EQ(with([](SloshSpec& s) { s.direction.setZero(); }),
            "m.yaml: appendages[0].direction: must be finite and non-zero");
  EXPECT_EQ(with([](SloshSpec& s) { s.parent = 3; }),
            "m.yaml: appendages[0].parent = 3: no such panel (rule: -1 for the hub or a panel's "
            "index)");
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::model
