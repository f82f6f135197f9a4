// One column added to the hinge event table, in one place (run::HingeEventTable::
// Extend), is found in every output derived from it: the HDF5 file and its reader, the JSON
// of `deploysim analyze` and the Python package's event table.

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
#include "deploysim/run/hinge_events.h"
#include "deploysim/run/mission.h"
#include "trajectory_arrays.h"

namespace {

namespace py = pybind11;
using deploysim::run::HingeEvent;
using deploysim::run::HingeEventColumn;
using deploysim::run::HingeEventTable;

/// The kinetic energy's jump at the event: drive_work - energy_dissipated [J].
double Jump(const HingeEvent& e) { return e.drive_work - e.energy_dissipated; }

class HingeEventColumnsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    HingeEventColumn c;
    c.name = "kinetic_jump";
    c.units = "J";
    c.description = "jump of the kinetic energy at the event";
    c.number = [](const HingeEvent& e, double* out) { out[0] = Jump(e); };
    HingeEventTable::Extend(c);
  }
  void SetUp() override {
    // Releases and latches of the spring-driven wings (the first 100 s).
    deploysim::io::ProfileOverrides o;
    o.until = 100.0;
    deploysim::run::NullSink sink;
    r_ = deploysim::run::RunMission(
        *deploysim::io::LoadRun(
            std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/smallsat_spring_deploy.yaml",
            o),
        sink);
    ASSERT_GE(r_.hinge_events.size(), 2u);
    dir_ = std::filesystem::temp_directory_path() /
           ("deploysim_event_columns_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  deploysim::run::MissionResult r_;
  std::filesystem::path dir_;
};

TEST_F(HingeEventColumnsTest, AnAddedColumnIsInTheHdf5File) {
  const std::string path = (dir_ / "run.h5").string();
  deploysim::io::WriteTrajectoryFile(path, r_);
  const deploysim::io::TrajectoryFile f = deploysim::io::ReadTrajectoryFile(path);
  EXPECT_EQ(f.units.at("/events/hinge/kinetic_jump"), "J");
  // The standard columns read back bit for bit beside it.
  ASSERT_EQ(f.hinge_events.size(), r_.hinge_events.size());
  for (std::size_t i = 0; i < r_.hinge_events.size(); ++i) {
    EXPECT_EQ(f.hinge_events[i].event.drive_work, r_.hinge_events[i].drive_work);
    EXPECT_EQ(f.hinge_events[i].event.w_jump_B, r_.hinge_events[i].w_jump_B);
  }
}

TEST_F(HingeEventColumnsTest, AnAddedColumnIsInTheJson) {
  const std::string json = deploysim::cli::FormatJson(r_, nullptr);
  for (const HingeEvent& e : r_.hinge_events) {
    EXPECT_NE(json.find("\"drive_work\": " + deploysim::math::JsonNumber(e.drive_work) +
                        ", \"kinetic_jump\": " + deploysim::math::JsonNumber(Jump(e)) + "}"),
              std::string::npos)
        << json.substr(json.find("\"hinge_events\""), 600);
  }
}

TEST_F(HingeEventColumnsTest, AnAddedColumnIsInThePythonTable) {
  const py::scoped_interpreter python;
  const py::dict d = deploysim::python::HingeEventArrays(r_);
  const auto jump = d["kinetic_jump"].cast<py::array_t<double>>();
  ASSERT_EQ(static_cast<std::size_t>(jump.shape(0)), r_.hinge_events.size());
  for (std::size_t i = 0; i < r_.hinge_events.size(); ++i) {
    EXPECT_EQ(jump.at(static_cast<py::ssize_t>(i)), Jump(r_.hinge_events[i]));
  }
  EXPECT_EQ(d["w_jump_B"].cast<py::array_t<double>>().ndim(), 2);
  EXPECT_EQ(py::len(d["kind"]), r_.hinge_events.size());
}

}  // namespace
