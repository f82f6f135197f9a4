// One column added to the stage table (run::StageTable::Extend), or to the danger window
// table (run::DangerWindowTable::Extend), in one place, is found in every output derived
// from it: the HDF5 file (with its units, beside the standard columns read back bit for
// bit), the JSON of `deploysim analyze` and the Python package's tables.

#include <gtest/gtest.h>
#include <pybind11/embed.h>
#include <pybind11/numpy.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "deploysim/cli/report.h"
#include "deploysim/io/trajectory_file.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/math/number_format.h"
#include "deploysim/run/danger_windows.h"
#include "deploysim/run/mission.h"
#include "deploysim/run/stage_table.h"
#include "trajectory_arrays.h"

namespace {

namespace py = pybind11;
using deploysim::run::StageColumn;
using deploysim::run::StageRow;
using deploysim::run::StageTable;

double Duration(const StageRow& row) { return row.t_end - row.t_begin; }

class StageColumnsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    StageColumn c;
    c.name = "duration";
    c.units = "s";
    c.description = "length of the stage";
    c.number = [](const StageRow& row, double* out) { out[0] = Duration(row); };
    StageTable::Extend(c);
  }
  void SetUp() override {
    // The main job's stages: holds and moves of both wings.
    deploysim::run::NullSink sink;
    r_ = deploysim::run::RunMission(
        *deploysim::io::LoadRun(std::string(DEPLOYSIM_SOURCE_DIR) +
                                "/deployment_profiles/smallsat_three_stage.yaml"),
        sink);
    ASSERT_GE(r_.stages.size(), 3u);
    dir_ = std::filesystem::temp_directory_path() /
           ("deploysim_stage_columns_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  deploysim::run::MissionResult r_;
  std::filesystem::path dir_;
};

TEST_F(StageColumnsTest, AnAddedColumnIsInTheHdf5File) {
  const std::string path = (dir_ / "run.h5").string();
  deploysim::io::WriteTrajectoryFile(path, r_);
  const deploysim::io::TrajectoryFile f = deploysim::io::ReadTrajectoryFile(path);
  EXPECT_EQ(f.units.at("/stages/duration"), "s");
  // The standard columns read back bit for bit beside it.
  const std::vector<StageRow> rows = deploysim::run::StageRows(r_);
  ASSERT_EQ(f.stages.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(f.stages[i].name, rows[i].name);
    EXPECT_EQ(f.stages[i].from, rows[i].from);
    EXPECT_EQ(f.stages[i].moments_end, rows[i].moments_end);
    EXPECT_EQ(f.stages[i].separatrix_distance, rows[i].separatrix_distance);
    EXPECT_EQ(f.stages[i].rigid_body_only, rows[i].rigid_body_only);
  }
}

TEST_F(StageColumnsTest, AnAddedColumnIsInTheJson) {
  const std::string json = deploysim::cli::FormatJson(r_, nullptr);
  for (const StageRow& row : deploysim::run::StageRows(r_)) {
    EXPECT_NE(
        json.find("\"rigid_body_only\": " + std::string(row.rigid_body_only ? "true" : "false") +
                  ", \"duration\": " + deploysim::math::JsonNumber(Duration(row)) +
                  ", \"predicted_flips\": "),
        std::string::npos)
        << json.substr(json.find("\"stages\""), 800);
  }
}

TEST_F(StageColumnsTest, AnAddedColumnIsInThePythonTable) {
  const py::scoped_interpreter python;
  const py::list stages = deploysim::python::StageRowDicts(r_);
  const std::vector<StageRow> rows = deploysim::run::StageRows(r_);
  ASSERT_EQ(py::len(stages), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const py::dict d = stages[i].cast<py::dict>();
    EXPECT_EQ(d["duration"].cast<double>(), Duration(rows[i]));
    EXPECT_EQ(d["name"].cast<std::string>(), rows[i].name);
    EXPECT_EQ(d["moments_end"].cast<py::array_t<double>>().size(), 3);
  }
}

double Length(const deploysim::run::DangerWindow& w) { return w.t_end - w.t_begin; }

class DangerWindowColumnsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    deploysim::run::DangerWindowColumn c;
    c.name = "length";
    c.units = "s";
    c.description = "length of the window";
    c.value = Length;
    deploysim::run::DangerWindowTable::Extend(c);
  }
  void SetUp() override {
    // The wing nut spins about its intermediate axis: in danger throughout.
    deploysim::run::NullSink sink;
    r_ = deploysim::run::RunMission(*deploysim::io::LoadRun(std::string(DEPLOYSIM_SOURCE_DIR) +
                                                            "/deployment_profiles/wing_nut.yaml"),
                                    sink);
    ASSERT_GE(r_.danger_windows.size(), 1u);
    dir_ = std::filesystem::temp_directory_path() /
           ("deploysim_window_columns_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  deploysim::run::MissionResult r_;
  std::filesystem::path dir_;
};

TEST_F(DangerWindowColumnsTest, AnAddedColumnIsInEveryOutput) {
  const std::string path = (dir_ / "run.h5").string();
  deploysim::io::WriteTrajectoryFile(path, r_);
  const deploysim::io::TrajectoryFile f = deploysim::io::ReadTrajectoryFile(path);
  EXPECT_EQ(f.units.at("/danger_windows/length"), "s");
  ASSERT_EQ(f.danger_windows.size(), r_.danger_windows.size());
  EXPECT_EQ(f.danger_windows[0].t_end, r_.danger_windows[0].t_end);
  const std::string json = deploysim::cli::FormatJson(r_, nullptr);
  const deploysim::run::DangerWindow& w = r_.danger_windows[0];
  EXPECT_NE(json.find("{\"t_begin\": " + deploysim::math::JsonNumber(w.t_begin) +
                      ", \"t_end\": " + deploysim::math::JsonNumber(w.t_end) +
                      ", \"length\": " + deploysim::math::JsonNumber(Length(w)) + "}"),
            std::string::npos)
      << json.substr(json.find("\"danger_windows\""), 300);
  const py::scoped_interpreter python;
  const py::dict d = deploysim::python::DangerWindowArrays(r_);
  const auto length = d["length"].cast<py::array_t<double>>();
  ASSERT_EQ(static_cast<std::size_t>(length.size()), r_.danger_windows.size());
  EXPECT_EQ(length.at(0), Length(w));
}

}  // namespace
