#pragma once

/// Shared fixtures of the sweep tests: a scratch directory per test, sweep files written
/// into it, and a bit-for-bit comparison of two results tables.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sweep/results_file.h"

namespace deploysim::sweep::testing {

/// The repository's small-satellite profile (600 s, exact coupling).
inline std::string SmallsatProfile() {
  return std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/smallsat_three_stage.yaml";
}

class SweepDirTest : public ::testing::Test {
 public:
  void SetUp() override {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() / "deploysim_sweep_tests" /
           (std::string(info->test_suite_name()) + "." + info->name() + "." +
            std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  std::string Write(const std::string& name, const std::string& text) const {
    const std::filesystem::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }

  /// Names in the test's directory, sorted.
  std::vector<std::string> Entries() const {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir_)) {
      names.push_back(e.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  std::filesystem::path dir_;
};

/// Bit-for-bit equality of the /cases tables (NaN == NaN when the bits agree).
inline void ExpectSameCases(const SweepTable& a, const SweepTable& b) {
  ASSERT_EQ(a.columns, b.columns);
  ASSERT_EQ(a.rows, b.rows);
  for (const auto& [name, values] : a.numbers) {
    const std::vector<double>& other = b.numbers.at(name);
    ASSERT_EQ(values.size(), other.size()) << name;
    for (std::size_t i = 0; i < values.size(); ++i) {
      EXPECT_EQ(0, std::memcmp(&values[i], &other[i], sizeof(double)))
          << name << "[" << i << "]: " << values[i] << " vs " << other[i];
    }
  }
  for (const auto& [name, values] : a.texts) EXPECT_EQ(values, b.texts.at(name)) << name;
}

}  // namespace deploysim::sweep::testing
