// model::RebuildAppendages against the model file reader: a model's appendages expanded
// again from the specs it keeps and its declared body are the loaded ones to the bit (one
// rule in one place, model/appendages.h), and a changed spec changes what it generates.

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "deploysim/io/yaml_reader.h"
#include "deploysim/model/appendages.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

// A wing, a two-plane beam reduced to modes, a one-plane beam on the wing chosen by a
// frequency tolerance, and a tank on the wing (its fixed mass goes to the wing).
const char* const kModel = R"(name: rebuild
kind: hinged
hub: {mass: 50.0, box: [0.8, 0.8, 0.6]}
panels:
  - {name: wing, mass: 2.0, box: [0.6, 0.4, 0.02], hinge_point: [0, 0.4, 0.3],
     hinge_axis: [1, 0, 0], com_offset: [0, 0.3, 0.01]}
appendages:
  - {name: boom_px, kind: beam, root: [0.4, 0, 0], direction: [1, 0, 0], length: 2.0,
     mass_per_length: 0.2, radius: 0.01, bending: [{axis: [0, 1, 0], EI: 20},
     {axis: [0, 0, 1], EI: 30}], damping_ratio: 0.01, segments: 6, modes: 2}
  - {name: whip, kind: beam, parent: wing, root: [0, 0.6, 0], direction: [0, 1, 0],
     length: 1.0, mass_per_length: 0.1, radius: 0.005, bending: [{axis: [1, 0, 0], EI: 4}],
     damping_ratio: 0.02, frequency_tolerance: 0.05}
  - {name: tank, kind: slosh, parent: wing, direction: [0, 1, 0], axis: [0, 0, 1],
     damping_ratio: 0.01, spin_rate: 1.0, spin_radius: 0.6,
     tank: {shape: cylinder, center: [0, 0.3, 0], diameter: 0.2, height: 0.3,
            density: 1000, fill_fraction: 0.6}}
configurations:
  stowed: {hinge_angles_deg: [-60, 0, 0]}
)";

void ExpectSameBody(const model::HingedBody& a, const model::HingedBody& b) {
  EXPECT_EQ(a.hub.body.mass, b.hub.body.mass);
  EXPECT_EQ(a.hub.body.inertia_cm, b.hub.body.inertia_cm);
  EXPECT_EQ(a.hub.com_B, b.hub.com_B);
  ASSERT_EQ(a.panels.size(), b.panels.size());
  for (std::size_t i = 0; i < a.panels.size(); ++i) {
    const model::Panel& p = a.panels[i];
    const model::Panel& q = b.panels[i];
    EXPECT_EQ(p.name, q.name);
    EXPECT_EQ(p.parent, q.parent) << p.name;
    EXPECT_EQ(p.body.mass, q.body.mass) << p.name;
    EXPECT_EQ(p.body.inertia_cm, q.body.inertia_cm) << p.name;
    EXPECT_EQ(p.hinge_point_B, q.hinge_point_B) << p.name;
    EXPECT_EQ(p.hinge_axis_B, q.hinge_axis_B) << p.name;
    EXPECT_EQ(p.com_offset_B, q.com_offset_B) << p.name;
  }
}

TEST(AppendageRebuild, ExpandingAgainGivesTheLoadedModelExactly) {
  const model::Model loaded = ReadModelText(kModel, "m.yaml");
  ASSERT_EQ(loaded.appendages.size(), 3u);
  EXPECT_EQ(loaded.declared.panels.size(), 1u);
  // The tank's fixed mass went onto the wing, not onto the declared wing.
  EXPECT_GT(loaded.hinged.panels[0].body.mass, loaded.declared.panels[0].body.mass);
  model::Model m = loaded;
  model::RebuildAppendages(m);
  ExpectSameBody(m.hinged, loaded.hinged);
  for (std::size_t k = 0; k < m.appendages.size(); ++k) {
    const model::Appendage& a = m.appendages[k];
    const model::Appendage& b = loaded.appendages[k];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.root, b.root);
    EXPECT_EQ(a.hinges, b.hinges);
    EXPECT_EQ(a.stiffness, b.stiffness);
    EXPECT_EQ(a.damping, b.damping);
    EXPECT_EQ(a.segments, b.segments);
    EXPECT_EQ(a.modes, b.modes);
    EXPECT_EQ(a.chain_frequencies, b.chain_frequencies);
  }
}

TEST(AppendageRebuild, AChangedSpecChangesWhatItGenerates) {
  model::Model m = ReadModelText(kModel, "m.yaml");
  const model::Model loaded = m;
  auto beam = std::make_shared<model::BeamSpec>(*m.appendages[1].beam);
  beam->planes[0].bending_stiffness *= 4.0;  // k = EI / l: x4; omega_1 x2: c = 2 zeta k / w1 x2
  m.appendages[1].beam = beam;
  auto slosh = std::make_shared<model::SloshSpec>(*m.appendages[2].slosh);
  slosh->tank->fill_fraction = 0.3;
  m.appendages[2].slosh = slosh;
  model::RebuildAppendages(m);
  const model::Appendage& whip = m.appendages[1];
  for (std::size_t i = 0; i < whip.hinges.size(); ++i) {
    EXPECT_EQ(whip.stiffness[i], 4.0 * loaded.appendages[1].stiffness[i]);
    EXPECT_NEAR(whip.damping[i], 2.0 * loaded.appendages[1].damping[i], 1e-12 * whip.damping[i]);
  }
  const int bob = m.appendages[2].hinges[1];
  const model::SloshTankPendulum p = model::CylinderTankPendulum(*slosh->tank);
  EXPECT_EQ(m.hinged.panels[static_cast<std::size_t>(bob)].body.mass, p.mass);
  EXPECT_EQ(m.hinged.panels[static_cast<std::size_t>(bob)].com_offset_B.y(), p.length);
  // The other beam is untouched.
  EXPECT_EQ(m.appendages[0].stiffness, loaded.appendages[0].stiffness);
}

TEST(AppendageRebuild, RefusesAnAppendageWithoutASpec) {
  model::Model m = ReadModelText(kModel, "m.yaml");
  m.appendages[2].slosh.reset();
  try {
    model::RebuildAppendages(m);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("m.yaml: appendages[2] (tank): has no spec"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
