// CSV trajectories (io/trajectory_csv.h): a header of names with units, values that read
// back exactly, the hinge rates beside the hinge angles, and nothing left on a failure.

#include "deploysim/io/trajectory_csv.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/synthetic_mission.h"
#include "temp_dir_test.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;
using run::MissionResult;
using testing::kPanels;
using testing::SyntheticResult;

class TrajectoryCsvTest : public testing::TempDirTest {};

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) cells.push_back(cell);
  return cells;
}

TEST_F(TrajectoryCsvTest, CsvHasUnitsInTheHeaderAndExactValues) {
  const MissionResult r = SyntheticResult(schedule::Mode::kGeometry);
  const run::Trajectory& t = r.trajectory;
  const std::string path = Path("out.csv");
  WriteTrajectoryCsv(path, t);
  std::ifstream in(path);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  const std::vector<std::string> header = Split(line);
  // The columns before the free-hinge outputs keep their positions; energy_spring, energy_total and
  // the hinge rates follow, then the five energy-ledger columns.
  const std::size_t old_columns = 1 + 3 + 3 + 4 + 6 + 3 + 3 + 3 + 1 + 1 + 3 + 1 + kPanels;
  const std::size_t columns = old_columns + 2 + kPanels + 5;
  ASSERT_EQ(header.size(), columns) << line;
  EXPECT_EQ(header[0], "time [s]");
  EXPECT_EQ(header[1], "H_B_x [kg m^2/s]");
  EXPECT_EQ(header[7], "q_NB_w [1]");
  EXPECT_EQ(header[11], "J_B_xx [kg m^2]");
  EXPECT_EQ(header[26], "energy [J]");
  EXPECT_EQ(header[27], "energy_rigid [J]");
  EXPECT_EQ(header[old_columns - 2], "hinge_angle_0 [rad]");
  EXPECT_EQ(header[old_columns - 1], "hinge_angle_1 [rad]");
  EXPECT_EQ(header[old_columns], "energy_spring [J]");
  EXPECT_EQ(header[old_columns + 1], "energy_total [J]");
  EXPECT_EQ(header[old_columns + 2], "hinge_rate_0 [rad/s]");
  EXPECT_EQ(header[columns - 6], "hinge_rate_1 [rad/s]");
  EXPECT_EQ(header[columns - 5], "work_damper [J]");
  EXPECT_EQ(header[columns - 1], "work_impacts [J]");
  for (const std::string& h : header) {
    EXPECT_NE(h.find(" ["), std::string::npos) << "no unit: " << h;
  }
  std::size_t k = 0;
  while (std::getline(in, line)) {
    ASSERT_LT(k, t.size());
    const std::vector<std::string> cells = Split(line);
    ASSERT_EQ(cells.size(), columns);
    auto value = [&](std::size_t i) { return std::strtod(cells[i].c_str(), nullptr); };
    EXPECT_EQ(value(0), t.time[k]);
    EXPECT_EQ(value(2), t.H_B[k].y());
    EXPECT_EQ(value(7), t.q_NB[k].w());
    EXPECT_EQ(value(8), t.q_NB[k].x());
    EXPECT_EQ(value(14), t.J_B[k](0, 1));  // J_B_xy
    EXPECT_EQ(value(26), t.energy[k]);
    EXPECT_EQ(value(27), t.energy_rigid[k]);
    EXPECT_EQ(value(old_columns - 1), t.hinge_angles[k][1]);
    EXPECT_EQ(value(old_columns), t.energy_spring[k]);
    EXPECT_EQ(value(old_columns + 1), t.energy[k] + t.energy_spring[k]);
    EXPECT_EQ(value(old_columns + 2), t.hinge_rates[k][0]);
    EXPECT_EQ(value(columns - 6), t.hinge_rates[k][1]);
    EXPECT_EQ(value(columns - 5), t.work_damper[k]);
    EXPECT_EQ(value(columns - 1), t.work_impacts[k]);
    ++k;
  }
  EXPECT_EQ(k, t.size());
  EXPECT_EQ(Entries(), std::vector<std::string>{"out.csv"});
}

TEST_F(TrajectoryCsvTest, CsvNeedsHingeRatesBesideHingeAngles) {
  run::Trajectory t = SyntheticResult(schedule::Mode::kGeometry).trajectory;
  t.hinge_rates.clear();
  EXPECT_THROW(WriteTrajectoryCsv(Path("out.csv"), t), std::invalid_argument);
  t = SyntheticResult(schedule::Mode::kGeometry).trajectory;
  t.hinge_rates[1] = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(WriteTrajectoryCsv(Path("out.csv"), t), std::invalid_argument);
  t = SyntheticResult(schedule::Mode::kGeometry).trajectory;
  t.energy_spring.pop_back();
  EXPECT_THROW(WriteTrajectoryCsv(Path("out.csv"), t), std::invalid_argument);
  EXPECT_TRUE(Entries().empty());
}

TEST_F(TrajectoryCsvTest, CsvFailureLeavesNothing) {
  EXPECT_THROW(WriteTrajectoryCsv(Path("missing/out.csv"),
                                  SyntheticResult(schedule::Mode::kTensor).trajectory),
               std::runtime_error);
  fs::create_directory(Path("taken.csv"));
  EXPECT_THROW(
      WriteTrajectoryCsv(Path("taken.csv"), SyntheticResult(schedule::Mode::kTensor).trajectory),
      std::runtime_error);
  EXPECT_EQ(Entries(), std::vector<std::string>{"taken.csv"});
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

// docs/file_formats.md lists every column of the trajectory schema with its shape and
// units, as the file has them.
}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
