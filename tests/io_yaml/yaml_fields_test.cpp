// The strict YAML layer (io/yaml_fields.h): opaque nodes keep plain and quoted scalars
// apart; file paths are relative to the document and must be readable.

#include "deploysim/io/yaml_fields.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

std::string Repo(const std::string& relative) {
  return std::string(DEPLOYSIM_SOURCE_DIR) + "/" + relative;
}

TEST(YamlFieldsTest, OpaqueNodesKeepPlainAndQuotedScalarsApart) {
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

TEST(YamlFieldsTest, FilePathIsRelativeToTheDocumentAndMustBeReadable) {
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
