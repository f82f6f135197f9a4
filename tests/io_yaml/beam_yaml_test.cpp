// Model files with `appendages:` of kind beam (model/flexible_beam.h; docs/file_formats.md,
// "Appendages"): read into the chain model::AddBeam builds, with one line for a bad key,
// kind or value naming the file, the key and the rule.

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "deploysim/io/yaml_reader.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

/// A hub and one appendage whose flow-mapping entries are `entries`, straight.
std::string ModelText(const std::string& entries) {
  return "name: boom_test\n"
         "kind: hinged\n"
         "hub: {mass: 50, box: [0.8, 0.8, 0.6]}\n"
         "appendages:\n"
         "  - {name: boom, " +
         entries +
         "}\n"
         "configurations:\n"
         "  straight: {hinge_angles_deg: [0]}\n";
}

const std::string kBeam =
    "kind: beam, root: [0.4, 0, 0], direction: [1, 0, 0], length: 2.0, mass_per_length: 0.2, "
    "radius: 0.01, bending: [{axis: [0, 1, 0], EI: 20}], damping_ratio: 0.01, segments: 6";

std::string Error(const std::string& text) {
  try {
    ReadModelText(text, "m.yaml");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

TEST(BeamYaml, ReadsTheChain) {
  const model::Model m = ReadModelText(ModelText(kBeam + ", modes: 2"), "m.yaml");
  ASSERT_EQ(m.appendages.size(), 1u);
  EXPECT_EQ(m.appendages[0].segments, 6);
  EXPECT_EQ(m.appendages[0].hinges.size(), 6u);
  EXPECT_EQ(m.appendages[0].modes.cols(), 2);
  EXPECT_EQ(m.hinged.panels.size(), 7u);                             // the stub and 6 segments
  EXPECT_DOUBLE_EQ(m.appendages[0].stiffness[0], 20.0 / (2.0 / 6));  // EI / l
}

TEST(BeamYaml, BadInputIsOneLineNamingTheKey) {
  // An unknown key is named against the beam's own keys, not every kind's.
  const std::string typo = Error(ModelText(kBeam + ", mass_per_lenght: 0.2"));
  EXPECT_EQ(typo.rfind("m.yaml: appendages[0].mass_per_lenght = 0.2: unknown key (allowed: name, "
                       "kind, parent, root,",
                       0),
            0u)
      << typo;
  EXPECT_EQ(typo.find("pivot"), std::string::npos) << typo;
  EXPECT_EQ(Error(ModelText("kind: bem, length: 1")),
            "m.yaml: appendages[0].kind = bem: unknown appendage kind (valid: beam, slosh)");
  EXPECT_NE(Error(ModelText("length: 1")).find("appendages[0].kind: required key is missing"),
            std::string::npos);
  EXPECT_EQ(Error(ModelText(kBeam + ", modes: 9")),
            "m.yaml: appendages[0].modes = 9: must be at most the segments (rule: 1 <= modes <= "
            "segments)");
  const std::string nan = Error(ModelText(
      "kind: beam, root: [0.4, 0, 0], direction: [1, 0, 0], length: 2.0, mass_per_length: 0.2, "
      "radius: 0.01, bending: [{axis: [0, 1, 0], EI: .nan}], segments: 6"));
  EXPECT_EQ(nan.rfind("m.yaml: appendages[0].bending[0].EI = .nan", 0), 0u) << nan;
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
