// Model files with `appendages:` of kind slosh (model/slosh.h; docs/file_formats.md,
// "Appendages"): read into the same pendulum as model::AddSlosh builds, configurations
// without an angle for a pendulum (it has no root hinge), strict keys and ranges.

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "deploysim/io/yaml_reader.h"
#include "deploysim/model/slosh.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

/// A hub with one panel (`panel: true`) or none, and a slosh appendage whose keys are
/// `slosh` (YAML flow-mapping entries), with the configuration's angles `angles`.
std::string ModelText(const std::string& slosh, const std::string& angles, bool panel = false) {
  std::string t =
      "name: tank_test\n"
      "kind: hinged\n"
      "hub: {mass: 400, box: [1.0, 1.0, 2.0]}\n";
  if (panel) {
    t += "panels:\n"
         "  - {name: lid, mass: 5, box: [0.5, 0.5, 0.02], hinge_point: [0.5, 0, 1],\n"
         "     hinge_axis: [0, 1, 0], com_offset: [0.25, 0, 0]}\n";
  }
  t += "appendages:\n"
       "  - {name: tank, kind: slosh, " +
       slosh +
       "}\n"
       "configurations:\n"
       "  initial: {hinge_angles_deg: " +
       angles + "}\n";
  return t;
}

const std::string kTank =
    "pivot: [0.6, 0, 0], direction: [1, 0, 0], axis: [0, 0, 1], mass: 30, length: 0.2, "
    "fixed_mass: 50, fixed_point: [0.65, 0, 0]";

std::string Refusal(const std::string& text) {
  try {
    (void)ReadModelText(text, "m.yaml");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(SloshYaml, ReadsThePendulumAsAddSloshBuildsIt) {
  const model::Model m = ReadModelText(ModelText(kTank + ", damping: 0.3", "[]"), "m.yaml");
  ASSERT_EQ(m.appendages.size(), 1u);
  const model::Appendage& a = m.appendages[0];
  EXPECT_EQ(a.kind, model::Appendage::Kind::kSlosh);
  EXPECT_EQ(a.root, -1);
  EXPECT_EQ(a.damping, (std::vector<double>{0.3, 0.3}));
  ASSERT_EQ(m.hinged.panels.size(), 2u);
  EXPECT_EQ(m.hinged.panels[1].name, "tank_b");
  EXPECT_EQ(m.hinged.panels[1].body.mass, 30.0);
  EXPECT_NEAR(m.hinged.hub.body.mass, 450.0, 1e-12);
  ASSERT_EQ(m.configurations.size(), 1u);
  EXPECT_EQ(m.configurations[0].hinge_angles.size(), 2);
  EXPECT_TRUE(m.configurations[0].hinge_angles.isZero(0.0));
}

TEST(SloshYaml, DampingRatioWithASpinRateInRpm) {
  // 60 / (2 pi) rpm = 1 rad/s, r = 0.6, L = 0.2: omega_out = 2 rad/s;
  // c = 2 0.05 2 30 0.04 = 0.24 N m s/rad.
  const std::string keys =
      kTank + ", damping_ratio: 0.05, spin_rate_rpm: 9.549296585513720, spin_radius: 0.6";
  const model::Model m = ReadModelText(ModelText(keys, "[]"), "m.yaml");
  EXPECT_NEAR(m.appendages[0].damping[0], 0.24, 1e-14);
}

TEST(SloshYaml, ConfigurationsHaveNoAngleForAPendulum) {
  const model::Model m =
      ReadModelText(ModelText(kTank + ", damping: 0.3", "[30]", /*panel=*/true), "m.yaml");
  ASSERT_EQ(m.configurations[0].hinge_angles.size(), 3);
  EXPECT_NEAR(m.configurations[0].hinge_angles[0], 3.14159265358979323846 / 6.0, 1e-15);
  EXPECT_EQ(m.configurations[0].hinge_angles[1], 0.0);
  EXPECT_NE(Refusal(ModelText(kTank + ", damping: 0.3", "[30, 0]", true))
                .find("configurations.initial.hinge_angles_deg = [30, 0]: must have one hinge "
                      "angle per panel (the model has 1 panels, in panel order)"),
            std::string::npos)
      << Refusal(ModelText(kTank + ", damping: 0.3", "[30, 0]", true));
}

TEST(SloshYaml, RefusesBadKeysAndRanges) {
  EXPECT_EQ(Refusal(ModelText(kTank + ", damping: -1", "[]")),
            "m.yaml: appendages[0].damping = -1: must be >= 0 [N m s/rad]");
  EXPECT_NE(Refusal(ModelText(kTank + ", damping: 0.3, segments: 4", "[]"))
                .find("appendages[0].segments"),
            std::string::npos);
  EXPECT_NE(Refusal(ModelText(kTank, "[]")).find("give exactly one of damping"), std::string::npos);
  const std::string no_point =
      "pivot: [0.6, 0, 0], direction: [1, 0, 0], mass: 30, length: 0.2, fixed_mass: 50, "
      "damping: 0.3";
  EXPECT_NE(
      Refusal(ModelText(no_point, "[]"))
          .find("appendages[0].fixed_mass = 50: fixed_mass [kg] and fixed_point [m] come together"),
      std::string::npos)
      << Refusal(ModelText(no_point, "[]"));
  EXPECT_NE(Refusal(ModelText(kTank + ", damping_ratio: 0.1, spin_rate: 1, spin_rate_rpm: 10, "
                                      "spin_radius: 1",
                              "[]"))
                .find("appendages[0].spin_rate_rpm = 10: give spin_rate [rad/s] or "
                      "spin_rate_rpm, not both"),
            std::string::npos);
  EXPECT_NE(Refusal(ModelText(kTank + ", damping: 0.3, parent: boom", "[]"))
                .find("appendages[0].parent = boom: no panel of that name"),
            std::string::npos);
  std::string text = ModelText(kTank + ", damping: 0.3", "[]");
  text.replace(text.find("kind: slosh"), 11, "kind: fluid");
  EXPECT_NE(Refusal(text).find("unknown appendage kind (valid: beam, slosh)"), std::string::npos);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
