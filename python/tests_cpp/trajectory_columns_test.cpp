// One column added to the trajectory schema, in one place (TrajectorySchema::Add), is
// found in every output derived from it: the HDF5 file and its reader, the CSV, the
// Python package's numpy arrays and the JSON of `deploysim analyze`.

#include <gtest/gtest.h>
#include <pybind11/embed.h>
#include <pybind11/numpy.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "deploysim/cli/report.h"
#include "deploysim/io/trajectory_file.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/math/number_format.h"
#include "deploysim/run/mission.h"
#include "deploysim/run/trajectory_schema.h"
#include "trajectory_arrays.h"

namespace {

namespace py = pybind11;
using deploysim::run::ColumnShape;
using deploysim::run::Trajectory;
using deploysim::run::TrajectoryColumn;
using deploysim::run::TrajectorySchema;

/// The standard schema plus two derived columns: the spin rate |w| (a scalar) and the
/// angular velocity in N (a vector).
TrajectorySchema Extended() {
  TrajectorySchema s = TrajectorySchema::Standard();
  TrajectoryColumn rate;
  rate.name = "spin_rate";
  rate.units = "rad/s";
  rate.description = "|w_NB_B|";
  rate.values = [](const Trajectory& t, std::size_t k, double* row) {
    row[0] = t.w_NB_B[k].norm();
  };
  s.Add(rate);
  TrajectoryColumn w_N;
  w_N.name = "w_NB_N";
  w_N.units = "rad/s";
  w_N.description = "angular velocity of B in N, N components";
  w_N.shape = ColumnShape::kVector3;
  w_N.csv_components = {"x", "y", "z"};
  w_N.csv_indices = {0, 1, 2};
  w_N.values = [](const Trajectory& t, std::size_t k, double* row) {
    const deploysim::math::Vec3 w = t.q_NB[k] * t.w_NB_B[k];
    for (int i = 0; i < 3; ++i) row[i] = w[i];
  };
  s.Add(w_N);
  return s;
}

class TrajectoryColumnsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // A hinge profile in geometry mode: per-panel columns too.
    r_ = deploysim::run::RunMission(deploysim::io::LoadProfile(
        std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/smallsat_spring_deploy.yaml"));
    ASSERT_GT(r_.trajectory.size(), 10u);
    dir_ = std::filesystem::temp_directory_path() /
           ("deploysim_columns_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  double Rate(std::size_t k) const { return r_.trajectory.w_NB_B[k].norm(); }
  deploysim::math::Vec3 WN(std::size_t k) const {
    return r_.trajectory.q_NB[k] * r_.trajectory.w_NB_B[k];
  }

  const TrajectorySchema schema_ = Extended();
  deploysim::run::MissionResult r_;
  std::filesystem::path dir_;
};

TEST_F(TrajectoryColumnsTest, AnAddedColumnIsInTheHdf5File) {
  const std::string path = (dir_ / "run.h5").string();
  deploysim::io::WriteTrajectoryFile(path, r_, schema_);
  const deploysim::io::TrajectoryFile f = deploysim::io::ReadTrajectoryFile(path, schema_);
  const std::size_t n = r_.trajectory.size();
  ASSERT_EQ(f.derived.at("spin_rate").size(), n);
  ASSERT_EQ(f.derived.at("w_NB_N").size(), 3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    EXPECT_EQ(f.derived.at("spin_rate")[k], Rate(k));
    for (int i = 0; i < 3; ++i) EXPECT_EQ(f.derived.at("w_NB_N")[3 * k + i], WN(k)[i]);
  }
  EXPECT_EQ(f.units.at("/spin_rate"), "rad/s");
  EXPECT_EQ(f.units.at("/w_NB_N"), "rad/s");
  // The standard reader reads the same file: the added datasets are extra ones.
  const deploysim::io::TrajectoryFile standard = deploysim::io::ReadTrajectoryFile(path);
  EXPECT_EQ(standard.derived.count("spin_rate"), 0u);
  EXPECT_EQ(standard.trajectory.w_NB_B, f.trajectory.w_NB_B);
}

TEST_F(TrajectoryColumnsTest, AnAddedColumnIsInTheCsv) {
  const std::string path = (dir_ / "run.csv").string();
  deploysim::io::WriteTrajectoryCsv(path, r_.trajectory, schema_);
  std::ifstream in(path);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  const std::string tail = ",spin_rate [rad/s],w_NB_N_x [rad/s],w_NB_N_y [rad/s],w_NB_N_z [rad/s]";
  ASSERT_GE(line.size(), tail.size());
  EXPECT_EQ(line.substr(line.size() - tail.size()), tail);
  for (std::size_t k = 0; std::getline(in, line); ++k) {
    std::vector<double> v;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
    ASSERT_GE(v.size(), 4u);
    EXPECT_EQ(v[v.size() - 4], Rate(k)) << "row " << k;
    for (int i = 0; i < 3; ++i) EXPECT_EQ(v[v.size() - 3 + i], WN(k)[i]) << "row " << k;
  }
}

TEST_F(TrajectoryColumnsTest, AnAddedColumnIsInTheJson) {
  const std::string json = deploysim::cli::FormatJson(r_, nullptr, schema_);
  const std::size_t last = r_.trajectory.size() - 1;
  using deploysim::math::FormatNumber;
  EXPECT_NE(json.find("\"spin_rate\": " + FormatNumber(Rate(last)) + ", "), std::string::npos)
      << json.substr(json.find("\"last_sample\""));
  EXPECT_NE(json.find("\"w_NB_N\": [" + FormatNumber(WN(last)[0]) + ", " +
                      FormatNumber(WN(last)[1]) + ", " + FormatNumber(WN(last)[2]) + "]"),
            std::string::npos);
  // Without the column, the standard JSON does not have it.
  EXPECT_EQ(deploysim::cli::FormatJson(r_, nullptr).find("spin_rate"), std::string::npos);
}

TEST_F(TrajectoryColumnsTest, AnAddedColumnIsInTheNumpyArrays) {
  const py::scoped_interpreter python;
  const std::size_t panels = deploysim::run::PanelCount(r_.trajectory);
  ASSERT_GT(panels, 0u);
  deploysim::python::TrajectoryArrays arrays(panels, 0, schema_);
  arrays.Append(r_.trajectory);
  const py::dict d = std::move(arrays).ToDict();
  const std::size_t n = r_.trajectory.size();
  const auto rate = d["spin_rate"].cast<py::array_t<double>>();
  ASSERT_EQ(rate.ndim(), 1);
  ASSERT_EQ(static_cast<std::size_t>(rate.shape(0)), n);
  const auto w_N = d["w_NB_N"].cast<py::array_t<double>>();
  ASSERT_EQ(w_N.ndim(), 2);
  ASSERT_EQ(w_N.shape(1), 3);
  const auto rate_view = rate.unchecked<1>();
  const auto w_view = w_N.unchecked<2>();
  for (std::size_t k = 0; k < n; ++k) {
    const auto i = static_cast<py::ssize_t>(k);
    EXPECT_EQ(rate_view(i), Rate(k));
    for (int j = 0; j < 3; ++j) EXPECT_EQ(w_view(i, j), WN(k)[j]);
  }
  // The standard columns keep their shapes beside the new ones.
  EXPECT_EQ(d["hinge_angles"].cast<py::array_t<double>>().shape(1),
            static_cast<py::ssize_t>(panels));
  EXPECT_EQ(d["J_B"].cast<py::array_t<double>>().ndim(), 3);
}

}  // namespace
