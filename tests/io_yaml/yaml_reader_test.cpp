// io_yaml on its own (this executable links deploysim::io_yaml and nothing above it, so
// it would not link if reading models and profiles needed the integrators or HDF5):
// the repository's models and profiles read, and the strict reader's opaque nodes.

#include "deploysim/io/yaml_reader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "deploysim/io/yaml_fields.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

std::string Repo(const std::string& relative) {
  return std::string(DEPLOYSIM_SOURCE_DIR) + "/" + relative;
}

TEST(IoYamlReader, ReadsEveryRepositoryModel) {
  int models = 0;
  for (const auto& e : std::filesystem::directory_iterator(Repo("models"))) {
    const model::Model m = LoadModel(e.path().string());
    EXPECT_FALSE(m.name.empty()) << e.path();
    EXPECT_FALSE(m.configurations.empty()) << e.path();
    ++models;
  }
  EXPECT_GE(models, 5);
}

TEST(IoYamlReader, ReadsAProfileAndTheModelItNames) {
  const schedule::Profile p = ReadProfile(Repo("deployment_profiles/smallsat_three_stage.yaml"));
  EXPECT_EQ(p.model.kind, model::ModelKind::kHinged);
  EXPECT_EQ(p.model.source,
            std::filesystem::path(Repo("models/smallsat.yaml")).lexically_normal().string());
  EXPECT_EQ(p.stages.size(), 5u);
  EXPECT_FALSE(p.integrator.method.empty());
}

TEST(IoYamlReader, TextEntryPointsReadAsTheFilesDoAndNameTheSource) {
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

TEST(IoYamlReader, ModeAndCouplingNames) {
  EXPECT_EQ(FindMode("geometry"), schedule::Mode::kGeometry);
  EXPECT_EQ(FindCoupling("exact"), schedule::Coupling::kExact);
  EXPECT_FALSE(FindMode("Geometry").has_value());
  EXPECT_EQ(ModeNames(), "tensor, geometry");
  EXPECT_THROW(ParseCoupling("rigid"), std::invalid_argument);
}

TEST(IoYamlFields, OpaqueNodesKeepPlainAndQuotedScalarsApart) {
  const yaml::YamlDocument doc("mem.yaml", "a: 12\nb: \"12\"\nc: [1, 2]\n");
  const yaml::Fields f(doc, doc.root(), "", {"a", "b", "c"});
  EXPECT_TRUE(f.Get("a").IsPlainScalar());
  EXPECT_FALSE(f.Get("b").IsPlainScalar());
  EXPECT_EQ(f.Get("b").Scalar(), "12");
  EXPECT_EQ(f.Get("c").Scalar(), "");
  EXPECT_EQ(yaml::Render(f.Get("c")), "[1, 2]");
  try {
    (void)f.Number("b");
    FAIL() << "a quoted number was read as a number";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "mem.yaml: b = \"12\": expected a number, not a quoted string");
  }
}

TEST(IoYamlFields, FilePathIsRelativeToTheDocumentAndMustBeReadable) {
  const std::string dir = Repo("deployment_profiles");
  const yaml::YamlDocument doc(dir + "/x.yaml", "model: ../models/wing_nut.yaml\nbad: nope.yaml\n");
  const yaml::Fields f(doc, doc.root(), "", {"model", "bad"});
  EXPECT_EQ(f.FilePath("model"),
            std::filesystem::path(Repo("models/wing_nut.yaml")).lexically_normal().string());
  try {
    (void)f.FilePath("bad");
    FAIL() << "a missing file was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("x.yaml: bad = nope.yaml: cannot read "),
              std::string::npos)
        << e.what();
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
