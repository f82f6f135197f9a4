// Model files (io/yaml_model.h), read by io_yaml on its own: this executable links
// deploysim::io_yaml and nothing above it, so it would not link if reading a model needed
// the integrators or HDF5.

#include "deploysim/io/yaml_model.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

std::string Repo(const std::string& relative) {
  return std::string(DEPLOYSIM_SOURCE_DIR) + "/" + relative;
}

TEST(YamlModelTest, ReadsEveryRepositoryModel) {
  int models = 0;
  for (const auto& e : std::filesystem::directory_iterator(Repo("models"))) {
    const model::Model m = LoadModel(e.path().string());
    EXPECT_FALSE(m.name.empty()) << e.path();
    EXPECT_FALSE(m.configurations.empty()) << e.path();
    ++models;
  }
  EXPECT_GE(models, 5);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
