// A slosh pendulum given by its tank (model/slosh.h SloshTank): the upright cylinder's
// first-mode pendulum against NASA SP-106 / Dodge 2000 at several fill fractions, its
// placement along the tank's axis and its ranges.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "deploysim/model/slosh.h"

namespace deploysim::model {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Vec3;

constexpr double kRoundoff = 1e-13;  // relative: a few roundings

/// A 1.2 m wide, 1.0 m high cylinder holding 600 kg when full.
SloshTank Cylinder(double fill) {
  SloshTank t;
  t.center = Vec3(0.9, 0.0, 0.1);
  t.diameter = 1.2;
  t.height = 1.0;
  t.liquid_mass_full = 600.0;
  t.fill_fraction = fill;
  return t;
}

SloshSpec TankSpec(double fill) {
  SloshSpec s;
  s.name = "tank";
  s.direction = Vec3(3.0, 0.0, 0.0);  // outward along x: the bottom at x = 0.9 + 0.5
  s.axis = Vec3(0.0, 0.0, 1.0);
  s.tank = Cylinder(fill);
  s.damping = 0.1;
  return s;
}

HingedBody HubBody() {
  HingedBody b;
  b.hub.body.mass = 400.0;
  b.hub.body.inertia_cm = Eigen::Vector3d(150, 160, 90).asDiagonal();
  return b;
}

TEST(SloshTank, CylinderPendulumFollowsTheHandbookAtSeveralFills) {
  // m1 and L1 from m1 / m = (d / 4.4 h) tanh(3.68 h / d), L1 = (d / 3.68) coth(3.68 h / d),
  // evaluated separately (Python, double precision) for d = 1.2 m, H = 1 m, 600 kg full.
  struct Row {
    double fill, m1, L1;
  };
  for (const Row& r : {Row{0.25, 105.54332638513947, 0.5055713669640363},
                       Row{0.5, 149.07162918688786, 0.35794660651068966},
                       Row{0.9, 162.33058958760193, 0.32870997345617825}}) {
    const SloshTankPendulum p = CylinderTankPendulum(Cylinder(r.fill));
    EXPECT_NEAR(p.liquid_mass, 600.0 * r.fill, kRoundoff * 600.0) << r.fill;
    EXPECT_NEAR(p.liquid_height, r.fill, kRoundoff) << r.fill;
    EXPECT_NEAR(p.mass, r.m1, kRoundoff * r.m1) << r.fill;
    EXPECT_NEAR(p.length, r.L1, kRoundoff * r.L1) << r.fill;
    EXPECT_NEAR(p.fixed_mass, p.liquid_mass - r.m1, kRoundoff * 600.0) << r.fill;
    // The model's centre of mass is the liquid's (h/2 above the bottom).
    EXPECT_NEAR((p.mass * p.bob_height + p.fixed_mass * p.fixed_height) / p.liquid_mass,
                0.5 * r.fill, kRoundoff);
    // The pivot is (d / 3.68) csch(3.68 h / d) above the free surface.
    EXPECT_NEAR(p.pivot_height - r.fill, 1.2 / 3.68 / std::sinh(3.68 * r.fill / 1.2), kRoundoff);
    EXPECT_NEAR(p.pivot_height - p.bob_height, r.L1, kRoundoff);
  }
}

TEST(SloshTank, SloshFrequencyIsTheCylindersFirstMode) {
  // g / L1 = (2 xi_1 g / d) tanh(2 xi_1 h / d): the first antisymmetric mode of an upright
  // cylinder, and a fuller tank sloshes with less of its liquid (m1 / m falls with h).
  double last_share = 1.0;
  for (double fill : {0.1, 0.3, 0.6, 1.0}) {
    const SloshTankPendulum p = CylinderTankPendulum(Cylinder(fill));
    const double g = 9.81;
    EXPECT_NEAR(g / p.length, 3.68 * g / 1.2 * std::tanh(3.68 * fill / 1.2),
                kRoundoff * g / p.length);
    EXPECT_LT(p.mass / p.liquid_mass, last_share);
    last_share = p.mass / p.liquid_mass;
  }
}

TEST(SloshTank, HydrazineTankOfTheSpinStabilizedStack) {
  // The tank worked by hand in models/spin_stabilized_tank.yaml's comment: d = 0.4 m,
  // hydrazine (1004 kg/m^3) 0.2 m deep, its bottom 0.55 m out along x: m_liquid 25.233 kg,
  // m1 10.905 kg, L1 0.11432 m, m0 14.328 kg (5 digits: the hand values' rounding), the
  // pivot at 0.314581 m and m0 at 0.466058 m from the spin axis.
  SloshTank t;
  t.center = Vec3(0.35, 0.0, 0.5);  // 0.55 m minus half the 0.4 m height
  t.diameter = 0.4;
  t.height = 0.4;
  t.density = 1004.0;
  t.fill_fraction = 0.5;
  const SloshTankPendulum p = CylinderTankPendulum(t);
  constexpr double kHand = 6e-5;  // relative: five significant digits
  EXPECT_NEAR(p.liquid_mass, 25.233, kHand * 25.233);
  EXPECT_NEAR(p.mass, 10.905, kHand * 10.905);
  EXPECT_NEAR(p.length, 0.11432, kHand * 0.11432);
  EXPECT_NEAR(p.fixed_mass, 14.328, kHand * 14.328);
  // The positions the model file gives to six digits (with the tables' 3.68 throughout).
  constexpr double kHandPosition = 1e-6;  // [m]
  EXPECT_NEAR(0.55 - p.pivot_height, 0.314581, kHandPosition);
  EXPECT_NEAR(0.55 - p.fixed_height, 0.466058, kHandPosition);
}

TEST(SloshTank, DensityGivesTheLiquidsMass) {
  SloshTank t = Cylinder(0.4);
  t.liquid_mass_full.reset();
  t.density = 1000.0;
  const double volume = 3.14159265358979323846 * 0.36 * 0.4;  // pi d^2 / 4 h
  EXPECT_NEAR(CylinderTankPendulum(t).liquid_mass, 1000.0 * volume, kRoundoff * 1000.0);
}

TEST(SloshTank, AddSloshPlacesThePendulumAlongTheTanksAxis) {
  HingedBody body = HubBody();
  const Appendage a = AddSlosh(body, TankSpec(0.5), "test");
  const SloshTankPendulum p = CylinderTankPendulum(Cylinder(0.5));
  const double bottom_x = 0.9 + 0.5;  // direction +x: the bottom is the outer end
  const Panel& link = body.panels[static_cast<std::size_t>(a.hinges[0])];
  const Panel& bob = body.panels[static_cast<std::size_t>(a.hinges[1])];
  EXPECT_NEAR(link.hinge_point_B.x(), bottom_x - p.pivot_height, kRoundoff);
  EXPECT_NEAR(link.hinge_point_B.z(), 0.1, kRoundoff);
  EXPECT_NEAR(bob.body.mass, p.mass, kRoundoff * p.mass);
  EXPECT_NEAR(bob.com_offset_B.x(), p.length, kRoundoff);
  // The hub carries m0 at bottom - h0 (its CoM moves towards it).
  EXPECT_NEAR(body.hub.body.mass, 400.0 + p.fixed_mass, kRoundoff * 400.0);
  const double x0 = bottom_x - p.fixed_height;
  EXPECT_NEAR(body.hub.com_B.x(), p.fixed_mass * x0 / (400.0 + p.fixed_mass), kRoundoff);
}

std::string Refusal(const SloshSpec& s) {
  HingedBody body = HubBody();
  try {
    (void)AddSlosh(body, s, "m.yaml: appendages[0]");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(SloshTank, RangesAreChecked) {
  SloshSpec s = TankSpec(0.0);
  EXPECT_EQ(Refusal(s), "m.yaml: appendages[0].tank.fill_fraction = 0: must be in (0, 1]");
  s = TankSpec(1.5);
  EXPECT_EQ(Refusal(s), "m.yaml: appendages[0].tank.fill_fraction = 1.5: must be in (0, 1]");
  s = TankSpec(0.5);
  s.tank->diameter = -1.0;
  EXPECT_EQ(Refusal(s), "m.yaml: appendages[0].tank.diameter = -1: must be > 0 [m]");
  s = TankSpec(0.5);
  s.tank->density = 800.0;
  EXPECT_NE(Refusal(s).find("exactly one of liquid_mass_full"), std::string::npos);
  s = TankSpec(0.5);
  s.mass = 3.0;
  EXPECT_NE(Refusal(s).find("tank: gives mass, length, pivot"), std::string::npos);
  EXPECT_EQ(Refusal(TankSpec(1.0)), "");
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::model
