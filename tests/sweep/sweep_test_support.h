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

#include "deploysim/sweep/results_file.h"
#include "temp_dir_test.h"

namespace deploysim::sweep::testing {

/// The repository's small-satellite profile (600 s, exact coupling).
inline std::string SmallsatProfile() {
  return std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/smallsat_three_stage.yaml";
}

/// The repository's spring deployment of the small satellite (a hinge profile, 600 s).
inline std::string SpringProfile() {
  return std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/smallsat_spring_deploy.yaml";
}

/// A scratch directory per test (tests/temp_dir_test.h).
class SweepDirTest : public deploysim::testing::TempDirTest {};

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
