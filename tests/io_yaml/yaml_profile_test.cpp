// Profile files (io/yaml_profile.h), read by io_yaml on its own (no integrators, no HDF5):
// a repository profile and the model it names, the text entry points, the mode and
// coupling names.

#include "deploysim/io/yaml_profile.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "deploysim/io/yaml_model.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

std::string Repo(const std::string& relative) {
  return std::string(DEPLOYSIM_SOURCE_DIR) + "/" + relative;
}

TEST(YamlProfileTest, ReadsAProfileAndTheModelItNames) {
  const schedule::Profile p = ReadProfile(Repo("deployment_profiles/smallsat_three_stage.yaml"));
  EXPECT_EQ(p.model.kind, model::ModelKind::kHinged);
  EXPECT_EQ(p.model.source,
            std::filesystem::path(Repo("models/smallsat.yaml")).lexically_normal().string());
  EXPECT_EQ(p.stages.size(), 5u);
  EXPECT_FALSE(p.integrator.method.empty());
}

TEST(YamlProfileTest, TextEntryPointsReadAsTheFilesDoAndNameTheSource) {
  const std::string path = Repo("deployment_profiles/smallsat_three_stage.yaml");
  const schedule::Profile file = ReadProfile(path);
  const schedule::Profile text = ReadProfileText(file.text, "<dict>", Repo("deployment_profiles"));
  EXPECT_EQ(text.source, "<dict>");
  EXPECT_EQ(text.model.source, file.model.source);
  EXPECT_EQ(text.model.text, file.model.text);
  ASSERT_EQ(text.stages.size(), file.stages.size());
  for (std::size_t i = 0; i < file.stages.size(); ++i) {
    EXPECT_EQ(text.stages[i].t_end, file.stages[i].t_end);
  }
  // A given model replaces the file the profile names.
  model::Model given = ReadModelText(file.model.text, "<model>");
  EXPECT_EQ(given.source, "<model>");
  const schedule::Profile with_model = ReadProfileText(file.text, "<dict>", "/nonexistent", &given);
  EXPECT_EQ(with_model.model.source, "<model>");
  // Messages name the source where a file's name the file.
  try {
    (void)ReadModelText(
        "name: m\nkind: tensors\nconfigurations: {a: {principal_moments: [1, 2, "
        "-3]}}\n",
        "<dict>");
    FAIL() << "accepted a negative moment";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("<dict>: configurations.a", 0), 0u) << e.what();
  }
}

TEST(YamlProfileTest, ModeAndCouplingNames) {
  EXPECT_EQ(FindMode("geometry"), schedule::Mode::kGeometry);
  EXPECT_EQ(FindCoupling("exact"), schedule::Coupling::kExact);
  EXPECT_FALSE(FindMode("Geometry").has_value());
  EXPECT_EQ(ModeNames(), "tensor, geometry");
  EXPECT_THROW(ParseCoupling("rigid"), std::invalid_argument);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
