// Model files' slosh appendages given by a tank (`tank:`, model/slosh.h SloshTank): read
// into the pendulum model::CylinderTankPendulum gives, strict keys.

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "deploysim/io/yaml_reader.h"
#include "deploysim/model/slosh.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

constexpr double kRoundoff = 1e-13;  // relative

std::string ModelText(const std::string& slosh) {
  return "name: tank_test\n"
         "kind: hinged\n"
         "hub: {mass: 400, box: [1.0, 1.0, 2.0]}\n"
         "appendages:\n"
         "  - {name: tank, kind: slosh, direction: [1, 0, 0], axis: [0, 0, 1], damping: 0.2, " +
         slosh +
         "}\n"
         "configurations:\n"
         "  initial: {hinge_angles_deg: []}\n";
}

const std::string kTank =
    "tank: {shape: cylinder, center: [0.8, 0, 0], diameter: 0.6, height: 0.9, "
    "liquid_mass_full: 120, fill_fraction: 0.4}";

std::string Refusal(const std::string& text) {
  try {
    (void)ReadModelText(text, "m.yaml");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(SloshTankYaml, ReadsTheTanksPendulum) {
  const model::Model m = ReadModelText(ModelText(kTank), "m.yaml");
  model::SloshTank t;
  t.center = math::Vec3(0.8, 0, 0);
  t.diameter = 0.6;
  t.height = 0.9;
  t.liquid_mass_full = 120.0;
  t.fill_fraction = 0.4;
  const model::SloshTankPendulum p = model::CylinderTankPendulum(t);
  ASSERT_EQ(m.hinged.panels.size(), 2u);
  EXPECT_NEAR(m.hinged.panels[1].body.mass, p.mass, kRoundoff * p.mass);
  EXPECT_NEAR(m.hinged.panels[1].com_offset_B.x(), p.length, kRoundoff);
  EXPECT_NEAR(m.hinged.panels[0].hinge_point_B.x(), 0.8 + 0.45 - p.pivot_height, kRoundoff);
  EXPECT_NEAR(m.hinged.hub.body.mass, 400.0 + p.fixed_mass, kRoundoff * 400.0);
}

TEST(SloshTankYaml, RefusesATankWithThePendulumsKeysOrAnotherShape) {
  EXPECT_NE(Refusal(ModelText(kTank + ", mass: 3"))
                .find("appendages[0].mass = 3: the tank gives the pendulum"),
            std::string::npos)
      << Refusal(ModelText(kTank + ", mass: 3"));
  std::string sphere = kTank;
  sphere.replace(sphere.find("cylinder"), 8, "sphere");
  EXPECT_NE(
      Refusal(ModelText(sphere)).find("appendages[0].tank.shape = sphere: unknown tank shape"),
      std::string::npos)
      << Refusal(ModelText(sphere));
  std::string both = kTank;
  both.replace(both.find("liquid_mass_full: 120"), 21, "liquid_mass_full: 120, density: 800");
  EXPECT_NE(Refusal(ModelText(both)).find("appendages[0].tank"), std::string::npos)
      << Refusal(ModelText(both));
  std::string empty = kTank;
  empty.replace(empty.find("fill_fraction: 0.4"), 18, "fill_fraction: 0");
  EXPECT_EQ(Refusal(ModelText(empty)),
            "m.yaml: appendages[0].tank.fill_fraction = 0: must be in (0, 1]");
  EXPECT_NE(Refusal(ModelText("length: 0.2")).find("pivot"), std::string::npos);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
