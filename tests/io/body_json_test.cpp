// The body record (io/body_json.h): a beam's generated panels drawn as rods that tile the
// beam, massless links drawn as nothing, the appendage's damping ratio read back, and
// docs/file_formats.md ("The body") explaining every member.

#include "deploysim/io/body_json.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "deploysim/model/flexible_beam.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

// Lengths and radii come back from mass properties (a few roundings).
constexpr double kDimsRelTol = 1e-12;

/// A hub with one panel of its own and a beam of `planes` bending planes, 4 segments.
model::Model BeamModel(int planes, double damping_ratio) {
  model::Model m;
  m.name = "beam_model";
  m.kind = model::ModelKind::kHinged;
  m.hinged.hub.body.mass = 50.0;
  m.hinged.hub.body.inertia_cm = math::Mat3::Identity() * 4.0;
  model::Panel wing;
  wing.name = "wing";
  wing.body.mass = 3.0;
  wing.body.inertia_cm = math::Mat3::Identity() * 0.2;
  wing.hinge_point_B = math::Vec3(0.0, 0.4, 0.0);
  wing.com_offset_B = math::Vec3(0.0, 0.5, 0.0);
  m.hinged.panels.push_back(wing);
  model::BeamSpec spec;
  spec.name = "boom";
  spec.root_point = math::Vec3(0.4, 0.0, 0.0);
  spec.direction = math::Vec3::UnitX();
  spec.length = 2.0;
  spec.mass_per_length = 0.2;
  spec.radius = 0.01;
  spec.planes.push_back({math::Vec3::UnitY(), 20.0});
  if (planes == 2) spec.planes.push_back({math::Vec3::UnitZ(), 30.0});
  spec.damping_ratio = damping_ratio;
  spec.segments = 4;
  m.appendages.push_back(model::AddBeam(m.hinged, spec, "test"));
  return m;
}

TEST(BodyJsonTest, BeamPartsAreRodsThatTileTheBeamAndLinksAreNotDrawn) {
  const model::Model m = BeamModel(2, 0.02);
  ASSERT_EQ(m.hinged.panels.size(), 1u + 1u + 2u * 4u);  // wing, stub, 4 x (link, segment)
  EXPECT_EQ(PanelShape(m, 0).shape, "box");
  double length = 0.0;
  int rods = 0, links = 0;
  for (int k = 1; k < static_cast<int>(m.hinged.panels.size()); ++k) {
    SCOPED_TRACE(m.hinged.panels[static_cast<std::size_t>(k)].name);
    const DrawnShape s = PanelShape(m, k);
    if (s.shape == "none") {
      EXPECT_EQ(m.hinged.panels[static_cast<std::size_t>(k)].body.mass, 0.0);
      ++links;
      continue;
    }
    ASSERT_EQ(s.shape, "rod");
    EXPECT_NEAR(s.radius, 0.01, kDimsRelTol * 0.01);
    EXPECT_NEAR((s.axis - math::Vec3::UnitX()).norm(), 0.0, kDimsRelTol);
    length += s.length;
    ++rods;
  }
  EXPECT_EQ(rods, 5);  // the stub [0, l/2], 3 segments of l, the tip half [L - l/2, L]
  EXPECT_EQ(links, 4);
  EXPECT_NEAR(length, 2.0, kDimsRelTol * 2.0);
  EXPECT_NEAR(PanelShape(m, 1).length, 0.25, kDimsRelTol);  // the stub: l / 2
}

TEST(BodyJsonTest, RecordsTheAppendageAndItsFirstModeDampingRatio) {
  const model::Model m = BeamModel(2, 0.02);
  const std::string json = BodyJson(m);
  EXPECT_NE(json.find("\"name\": \"wing\", \"parent\": -1"), std::string::npos) << json;
  EXPECT_NE(json.find("\"appendage\": null"), std::string::npos);
  EXPECT_NE(json.find("\"appendage\": \"boom\""), std::string::npos);
  EXPECT_NE(json.find("\"kind\": \"beam\", \"root\": 1, \"hinges\": [2, 3, 4, 5, 6, 7, 8, 9]"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("\"segments\": 4, \"planes\": 2, \"modes\": 0"), std::string::npos);
  // Rayleigh damping gives the first mode of each plane the ratio asked for.
  const std::size_t at = json.find("\"damping_ratio\": [");
  ASSERT_NE(at, std::string::npos);
  std::istringstream in(json.substr(at + 18));
  double z0 = 0.0, z1 = 0.0;
  char comma = 0;
  in >> z0 >> comma >> z1;
  EXPECT_NEAR(z0, 0.02, 1e-15);
  EXPECT_NEAR(z1, 0.02, 1e-15);
}

TEST(BodyJsonTest, RecordsTheModalCoordinates) {
  model::Model m;
  m.kind = model::ModelKind::kHinged;
  m.hinged.hub.body.mass = 10.0;
  m.hinged.hub.body.inertia_cm = math::Mat3::Identity();
  model::BeamSpec spec;
  spec.name = "boom";
  spec.length = 1.0;
  spec.mass_per_length = 0.1;
  spec.radius = 0.01;
  spec.planes.push_back({math::Vec3::UnitY(), 5.0});
  spec.planes.push_back({math::Vec3::UnitZ(), 5.0});
  spec.segments = 5;
  spec.modes = 2;
  m.appendages.push_back(model::AddBeam(m.hinged, spec, "test"));
  const std::string json = BodyJson(m);
  EXPECT_NE(json.find("\"planes\": 2, \"modes\": 4"), std::string::npos) << json;  // 2 a plane
}

TEST(BodyJsonTest, OnlyForHingedModels) {
  model::Model m;
  m.kind = model::ModelKind::kTensors;
  EXPECT_THROW(BodyJson(m), std::invalid_argument);
}

// docs/file_formats.md ("The body") explains every member of the record.
TEST(BodyJsonTest, FileFormatsExplainsEveryMember) {
  std::ifstream in(std::string(DEPLOYSIM_SOURCE_DIR) + "/docs/file_formats.md");
  ASSERT_TRUE(in);
  std::stringstream text;
  text << in.rdbuf();
  const std::size_t begin = text.str().find("### The body");
  ASSERT_NE(begin, std::string::npos);
  const std::string section = text.str().substr(begin, text.str().find("\n## ", begin) - begin);
  const std::string json = BodyJson(BeamModel(1, 0.01));
  std::set<std::string> names;
  for (std::size_t at = json.find('"'); at != std::string::npos;
       at = json.find('"', json.find('"', at + 1) + 1)) {
    const std::size_t end = json.find('"', at + 1);
    if (json.compare(end + 1, 1, ":") == 0) names.insert(json.substr(at + 1, end - at - 1));
  }
  for (const std::string& name : names) {
    EXPECT_NE(section.find("`" + name + "`"), std::string::npos) << name;
  }
  EXPECT_GT(names.size(), 20u);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
