// HDF5 trajectories (and their CSV twin, streamed beside them): bit-exact round trips
// of a synthetic mission, units on every dataset, readable by h5dump, and all-or-nothing
// writes. The CSV alone: trajectory_csv_test.cpp.

#include "deploysim/io/trajectory_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/analysis/motion_outcome.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/math/quaternion.h"
#include "io/synthetic_mission.h"
#include "run/hinge_fixtures.h"
#include "temp_dir_test.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;
using math::Mat3;
using math::Quat;
using math::Vec3;
using run::MissionResult;
using testing::kPanels;
using testing::SyntheticResult;

void ExpectSameTrajectory(const run::Trajectory& a, const run::Trajectory& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a.time[k], b.time[k]);
    EXPECT_EQ(a.H_B[k], b.H_B[k]);
    EXPECT_EQ(a.w_NB_B[k], b.w_NB_B[k]);
    EXPECT_EQ(a.q_NB[k].coeffs(), b.q_NB[k].coeffs());
    EXPECT_EQ(a.J_B[k], b.J_B[k]);
    EXPECT_EQ(a.principal_moments[k], b.principal_moments[k]);
    EXPECT_EQ(a.h_rel_B[k], b.h_rel_B[k]);
    EXPECT_EQ(a.h_N[k], b.h_N[k]);
    EXPECT_EQ(a.energy[k], b.energy[k]);
    EXPECT_EQ(a.energy_rigid[k], b.energy_rigid[k]);
    EXPECT_EQ(a.energy_spring[k], b.energy_spring[k]);
    EXPECT_EQ(a.euler_313[k], b.euler_313[k]);
    EXPECT_EQ(a.spin_axis_angle[k], b.spin_axis_angle[k]);
  }
  ASSERT_EQ(a.hinge_angles.size(), b.hinge_angles.size());
  for (std::size_t k = 0; k < a.hinge_angles.size(); ++k) {
    EXPECT_EQ(a.hinge_angles[k], b.hinge_angles[k]);
  }
  ASSERT_EQ(a.hinge_rates.size(), b.hinge_rates.size());
  for (std::size_t k = 0; k < a.hinge_rates.size(); ++k) {
    EXPECT_EQ(a.hinge_rates[k], b.hinge_rates[k]);
  }
}

/// The hinge events, latch times and 45-degree crossings of r as read back in f, bit for
/// bit (NaN latch times as NaN).
void ExpectSameHingeOutputs(const MissionResult& r, const TrajectoryFile& f) {
  EXPECT_TRUE(f.has_hinge_outputs);
  ASSERT_EQ(f.hinge_events.size(), r.hinge_events.size());
  for (std::size_t i = 0; i < r.hinge_events.size(); ++i) {
    SCOPED_TRACE("event " + std::to_string(i));
    const run::HingeEvent& a = r.hinge_events[i];
    const run::HingeEvent& b = f.hinge_events[i].event;
    EXPECT_EQ(b.kind, a.kind);
    EXPECT_EQ(b.t, a.t);
    EXPECT_EQ(b.panel, a.panel);
    EXPECT_EQ(f.hinge_events[i].panel_name,
              r.profile().model.hinged.panels[static_cast<std::size_t>(a.panel)].name);
    EXPECT_EQ(b.angle, a.angle);
    EXPECT_EQ(b.rate_before, a.rate_before);
    EXPECT_EQ(b.rate_after, a.rate_after);
    EXPECT_EQ(b.impulse, a.impulse);
    EXPECT_EQ(b.w_jump_B, a.w_jump_B);
    EXPECT_EQ(b.energy_dissipated, a.energy_dissipated);
  }
  ASSERT_EQ(f.hinge_latch_times.size(), r.latch_times.size());
  for (std::size_t k = 0; k < r.latch_times.size(); ++k) {
    if (std::isnan(r.latch_times[k])) {
      EXPECT_TRUE(std::isnan(f.hinge_latch_times[k])) << k;
    } else {
      EXPECT_EQ(f.hinge_latch_times[k], r.latch_times[k]) << k;
    }
  }
  EXPECT_EQ(f.spin_axis_45_times, r.spin_axis_45_crossings);
}

/// Output of a shell command ("" if it could not run).
std::string Capture(const std::string& command) {
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return out;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof(buf), pipe)) > 0) out.append(buf, n);
  ::pclose(pipe);
  return out;
}

bool HaveH5dump() { return std::system("h5dump --version > /dev/null 2>&1") == 0; }

class TrajectoryFileTest : public testing::TempDirTest {};

/// Samples [from, to) of t, column by column as the schema lists them.
run::Trajectory Slice(const run::Trajectory& t, std::size_t from, std::size_t to) {
  const run::TrajectorySchema& schema = run::TrajectorySchema::Standard();
  run::Trajectory b, one;
  for (std::size_t k = from; k < to; ++k) {
    for (const run::TrajectoryColumn& c : schema.columns()) {
      if (c.storage) c.storage->keep(one, t, k);
    }
    schema.Append(b, one);
  }
  return b;
}

TEST_F(TrajectoryFileTest, StreamedInBlocksIsTheSameFile) {
  for (schedule::Mode mode : {schedule::Mode::kTensor, schedule::Mode::kGeometry}) {
    const MissionResult r = SyntheticResult(mode);
    for (const char* f : {"whole.h5", "whole.csv", "streamed.h5", "streamed.csv"}) {
      fs::remove(Path(f));
    }
    WriteTrajectoryFile(Path("whole.h5"), r);
    WriteTrajectoryCsv(Path("whole.csv"), r.trajectory);
    {
      TrajectoryOutputs out(Path("streamed.h5"), Path("streamed.csv"), r.profile());
      const std::size_t n = r.trajectory.size();
      for (std::size_t from = 0; from < n; from += 3) {
        out.Append(Slice(r.trajectory, from, std::min(n, from + 3)));
      }
      out.Finish(r);
      EXPECT_FALSE(fs::exists(Path("streamed.h5"))) << "nothing at the targets before Commit";
      EXPECT_FALSE(fs::exists(Path("streamed.csv")));
      out.Commit();
    }
    const TrajectoryFile a = ReadTrajectoryFile(Path("whole.h5"));
    const TrajectoryFile b = ReadTrajectoryFile(Path("streamed.h5"));
    ExpectSameTrajectory(a.trajectory, b.trajectory);
    ExpectSameTrajectory(r.trajectory, b.trajectory);
    EXPECT_EQ(a.attributes, b.attributes);
    EXPECT_EQ(a.units, b.units);
    EXPECT_EQ(a.flip_times, b.flip_times);
    EXPECT_EQ(a.stages.size(), b.stages.size());
    EXPECT_EQ(a.derived, b.derived);
    ExpectSameHingeOutputs(r, b);
    std::ifstream ca(Path("whole.csv")), cb(Path("streamed.csv"));
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(ca), {}),
              std::string(std::istreambuf_iterator<char>(cb), {}));
    if (HaveH5dump()) {
      // Same names, shapes and types for h5dump (chunking is a storage detail).
      auto header = [](const std::string& path) {
        std::string h = Capture("h5dump -H '" + path + "' 2>&1");
        return h.substr(h.find('\n'));  // past the line that names the file
      };
      EXPECT_EQ(header(Path("whole.h5")), header(Path("streamed.h5")));
    }
  }
  EXPECT_EQ(Entries(),
            (std::vector<std::string>{"streamed.csv", "streamed.h5", "whole.csv", "whole.h5"}));
}

TEST_F(TrajectoryFileTest, AFailingStreamLeavesNeitherOutput) {
  const MissionResult r = SyntheticResult(schedule::Mode::kGeometry);
  Write("out.h5", "old h5");
  Write("out.h5.csv", "old csv");
  {
    TrajectoryOutputs out(Path("out.h5"), Path("out.h5.csv"), r.profile());
    out.Append(Slice(r.trajectory, 0, 2));
    run::Trajectory bad = Slice(r.trajectory, 2, 4);
    bad.hinge_angles[1] = Eigen::VectorXd::Zero(1);
    EXPECT_THROW(out.Append(bad), std::invalid_argument);
  }
  EXPECT_EQ(Entries(), (std::vector<std::string>{"out.h5", "out.h5.csv"}));
  std::ifstream f(Path("out.h5"));
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(f), {}), "old h5");
}

TEST_F(TrajectoryFileTest, RoundTripIsBitExactInGeometryMode) {
  const MissionResult r = SyntheticResult(schedule::Mode::kGeometry);
  const std::string path = Path("out.h5");
  WriteTrajectoryFile(path, r);
  const TrajectoryFile f = ReadTrajectoryFile(path);

  ExpectSameTrajectory(r.trajectory, f.trajectory);
  EXPECT_EQ(f.flip_times, r.flip_times);
  ASSERT_EQ(f.stages.size(), 2u);
  EXPECT_EQ(f.stages[0].name, "closed spin");
  EXPECT_EQ(f.stages[0].law, "hold");
  EXPECT_EQ(f.stages[0].from, "closed");
  EXPECT_EQ(f.stages[0].to, "closed");
  EXPECT_EQ(f.stages[0].t_begin, 0.0);
  EXPECT_EQ(f.stages[0].t_end, 1.0);
  EXPECT_EQ(f.stages[1].name, "deploy");
  EXPECT_EQ(f.stages[1].law, schedule::ToString(schedule::Law::kMinimumJerk));
  EXPECT_EQ(f.stages[1].from, "closed");
  EXPECT_EQ(f.stages[1].to, "open");
  EXPECT_EQ(f.stages[1].t_end, 1.5);
}

TEST_F(TrajectoryFileTest, StageAnalysisAndDangerWindowsRoundTrip) {
  const MissionResult r = SyntheticResult(schedule::Mode::kGeometry);
  const std::string path = Path("out.h5");
  WriteTrajectoryFile(path, r);
  const TrajectoryFile f = ReadTrajectoryFile(path);
  ASSERT_EQ(f.stages.size(), r.stages.size());
  for (std::size_t i = 0; i < f.stages.size(); ++i) {
    SCOPED_TRACE("stage " + std::to_string(i));
    const StageRow& row = f.stages[i];
    const run::StageReport& a = r.stages[i];
    EXPECT_EQ(row.index, static_cast<int>(i));
    EXPECT_EQ(row.rigid, a.rigid);
    EXPECT_EQ(row.moments_end, a.moments_end);
    EXPECT_EQ(row.spin_axis_role, analysis::ToString(a.spin_axis_end));
    EXPECT_EQ(row.regime, a.regime);
    EXPECT_EQ(row.one_minus_k2, a.one_minus_k2);
    EXPECT_EQ(row.separatrix_distance, a.separatrix_distance);
    EXPECT_EQ(row.predicted_flip_half_period, a.predicted_flip_half_period);
    EXPECT_EQ(row.predicted_flip_count, static_cast<long long>(a.predicted_flips.size()));
    EXPECT_EQ(row.observed_flip_count, static_cast<long long>(a.observed_flips.size()));
    EXPECT_EQ(row.max_flip_time_difference, a.max_flip_time_difference);
    EXPECT_EQ(row.caveat, a.caveat);
    EXPECT_EQ(row.rigid_body_only, a.rigid_body_only);
  }
  EXPECT_EQ(f.stages[0].spin_axis_role, "intermediate");
  EXPECT_EQ(f.stages[1].regime, "");
  EXPECT_TRUE(std::isinf(f.stages[1].predicted_flip_half_period));
  EXPECT_EQ(f.predicted_flip_times, (std::vector<double>{0.3 + 1e-9, 0.7}));
  ASSERT_EQ(f.danger_windows.size(), 2u);
  EXPECT_EQ(f.danger_windows[0].t_begin, 0.0);
  EXPECT_EQ(f.danger_windows[0].t_end, 0.75);
  EXPECT_EQ(f.danger_windows[1].t_begin, 1.25);
  EXPECT_EQ(f.danger_windows[1].t_end, 1.5);
}

TEST_F(TrajectoryFileTest, HingeOutputsRoundTripBitExact) {
  const MissionResult r = SyntheticResult(schedule::Mode::kGeometry);
  const std::string path = Path("out.h5");
  WriteTrajectoryFile(path, r);
  const TrajectoryFile f = ReadTrajectoryFile(path);
  ExpectSameTrajectory(r.trajectory, f.trajectory);  // hinge_rates, energy_spring included
  ASSERT_EQ(f.derived.at("energy_total").size(), r.trajectory.size());
  for (std::size_t k = 0; k < r.trajectory.size(); ++k) {
    EXPECT_EQ(f.derived.at("energy_total")[k],
              r.trajectory.energy[k] + r.trajectory.energy_spring[k]);
  }
  EXPECT_EQ(f.panel_names, (std::vector<std::string>{"wing_\xce\xb8", "boom"}));
  ExpectSameHingeOutputs(r, f);
  ASSERT_EQ(f.hinge_events.size(), 6u);
  EXPECT_EQ(f.hinge_events[0].event.kind, run::HingeEvent::Kind::kRelease);
  EXPECT_EQ(f.hinge_events[3].event.kind, run::HingeEvent::Kind::kRest);
  EXPECT_EQ(f.hinge_events[5].event.kind, run::HingeEvent::Kind::kJam);
  EXPECT_TRUE(std::isnan(f.hinge_latch_times[1])) << "never latched";
  ASSERT_EQ(f.stages.size(), 2u);
  EXPECT_EQ(f.stages[1].caveat, r.stages[1].caveat) << "UTF-8 survives";
  EXPECT_TRUE(f.stages[1].rigid_body_only);
  EXPECT_FALSE(f.stages[0].rigid_body_only);
}

// A hinge profile run end to end: its phases are the stage table (no configurations),
// its events, latch times and spring energy reach the file, streamed or whole.
TEST_F(TrajectoryFileTest, HingeProfileRunRoundTrips) {
  schedule::HingePlan plus = testing::SpringHinge(0.2, -30.0);
  plus.drive.latch.enabled = true;
  plus.drive.latch.angle = 0.0;
  schedule::HingePlan minus = plus;
  minus.drive.release.kind = schedule::Release::Kind::kAfterLatch;
  minus.drive.release.panel = 0;
  minus.drive.release.delay = 2.0;
  schedule::Profile profile = testing::SmallsatHingeProfile(plus, minus, 30.0);
  profile.integrator.rtol = 1e-10;
  ASSERT_TRUE(profile.is_hinge_profile());
  const MissionResult r = run::RunMission(profile);
  ASSERT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
  ASSERT_EQ(r.hinge_events.size(), 4u);  // release, latch, release, latch
  ASSERT_GE(r.stages.size(), 3u);        // phases, not profile stages (there are none)

  WriteTrajectoryFile(Path("whole.h5"), r);
  {
    // As `simulate` writes it: streamed while the mission runs.
    TrajectoryOutputs out(Path("streamed.h5"), Path("streamed.csv"), profile);
    const MissionResult again = run::RunMission(profile, out);
    out.Finish(again);
    out.Commit();
  }
  for (const char* name : {"whole.h5", "streamed.h5"}) {
    SCOPED_TRACE(name);
    const TrajectoryFile f = ReadTrajectoryFile(Path(name));
    ExpectSameTrajectory(r.trajectory, f.trajectory);
    ExpectSameHingeOutputs(r, f);
    EXPECT_EQ(f.panel_names, (std::vector<std::string>{"wing_plus_x", "wing_minus_x"}));
    EXPECT_EQ(f.hinge_events[1].panel_name, "wing_plus_x");
    EXPECT_EQ(f.hinge_events[3].panel_name, "wing_minus_x");
    EXPECT_TRUE(std::isfinite(f.hinge_latch_times[0]) && std::isfinite(f.hinge_latch_times[1]));
    ASSERT_EQ(f.stages.size(), r.stages.size());
    for (std::size_t i = 0; i < r.stages.size(); ++i) {
      SCOPED_TRACE("phase " + std::to_string(i));
      EXPECT_EQ(f.stages[i].index, static_cast<int>(i));
      EXPECT_EQ(f.stages[i].name, r.stages[i].name);
      EXPECT_EQ(f.stages[i].law, r.stages[i].law);
      EXPECT_EQ(f.stages[i].t_begin, r.stages[i].t_begin);
      EXPECT_EQ(f.stages[i].t_end, r.stages[i].t_end);
      EXPECT_EQ(f.stages[i].from, "");
      EXPECT_EQ(f.stages[i].to, "");
      EXPECT_EQ(f.stages[i].caveat, r.stages[i].caveat);
      EXPECT_FALSE(f.stages[i].caveat.empty());
      EXPECT_EQ(f.stages[i].rigid_body_only, r.stages[i].rigid_body_only);
    }
    EXPECT_EQ(f.stages.front().name, "free: wing_plus_x");
    EXPECT_EQ(f.stages.front().law, "free");
    // Springs store energy: the total is kinetic + spring, and without dampers it drops
    // only at the latches, by what they dissipate.
    const std::vector<double>& E = f.derived.at("energy_total");
    ASSERT_EQ(E.size(), f.trajectory.size());
    EXPECT_GT(f.trajectory.energy_spring.front(), 0.0);
    const double lost = r.hinge_events[1].energy_dissipated + r.hinge_events[3].energy_dissipated;
    EXPECT_GT(lost, 0.0);
    EXPECT_NEAR(E.front() - E.back(), lost, 1e-9 * E.front());
  }
  EXPECT_EQ(Entries(), (std::vector<std::string>{"streamed.csv", "streamed.h5", "whole.h5"}));
}

// A version 2 file written by deploysim before the free-hinge outputs (tests/io/data, made by
// `deploysim simulate deployment_profiles/smallsat_three_stage.yaml --dt 40` at commit
// 6f38410 and repacked with `h5repack -l CONTI` to drop the chunk padding) still reads:
// the free-hinge outputs are additions to schema version 2, absent there.
TEST_F(TrajectoryFileTest, ReadsAVersion2FileWrittenBeforeTheFreeHingeOutputs) {
  const std::string path =
      std::string(DEPLOYSIM_SOURCE_DIR) + "/tests/io/data/trajectory_v2_before_issue9.h5";
  const TrajectoryFile f = ReadTrajectoryFile(path);
  EXPECT_EQ(f.attributes.at("schema_version"), "2");
  EXPECT_FALSE(f.has_hinge_outputs);
  EXPECT_EQ(f.trajectory.size(), 16u);  // 0, 40, ..., 600 s
  EXPECT_EQ(f.trajectory.hinge_angles.size(), 16u);
  EXPECT_TRUE(f.trajectory.hinge_rates.empty());
  EXPECT_TRUE(f.trajectory.energy_spring.empty());
  EXPECT_EQ(f.derived.count("energy_total"), 0u);
  EXPECT_TRUE(f.panel_names.empty());
  EXPECT_TRUE(f.hinge_events.empty());
  EXPECT_TRUE(f.hinge_latch_times.empty());
  EXPECT_TRUE(f.spin_axis_45_times.empty());
  ASSERT_EQ(f.stages.size(), 5u);
  for (const StageRow& row : f.stages) {
    EXPECT_EQ(row.caveat, "");
    EXPECT_FALSE(row.rigid_body_only);
  }
  EXPECT_EQ(f.stages[1].from, "closed");
  EXPECT_FALSE(f.flip_times.empty());
}

TEST_F(TrajectoryFileTest, StageReportsMustMatchTheProfileStages) {
  MissionResult r = SyntheticResult(schedule::Mode::kTensor);
  r.stages.pop_back();
  EXPECT_THROW(WriteTrajectoryFile(Path("out.h5"), r), std::invalid_argument);
  r = SyntheticResult(schedule::Mode::kTensor);
  r.danger_windows = {{2.0, 1.0}};
  EXPECT_THROW(WriteTrajectoryFile(Path("out.h5"), r), std::invalid_argument);
  EXPECT_TRUE(Entries().empty());
}

TEST_F(TrajectoryFileTest, RootAttributes) {
  const MissionResult r = SyntheticResult(schedule::Mode::kGeometry);
  const std::string path = Path("out.h5");
  WriteTrajectoryFile(path, r);
  const std::map<std::string, std::string> a = ReadTrajectoryFile(path).attributes;
  for (const char* key :
       {"deploysim_version", "schema_version", "profile_name", "profile_source", "profile_text",
        "model_name", "model_source", "model_text", "integrator", "integrator_settings", "mode",
        "coupling", "termination", "termination_message", "statistics", "max_h_N_drift"}) {
    EXPECT_EQ(a.count(key), 1u) << key;
  }
  EXPECT_FALSE(a.at("deploysim_version").empty());
  EXPECT_EQ(a.at("schema_version"), std::to_string(kTrajectorySchemaVersion));
  EXPECT_EQ(a.at("profile_name"), "synthetic");
  EXPECT_EQ(a.at("profile_source"), "profiles/synthetic.yaml");
  EXPECT_EQ(a.at("profile_text"), r.profile().text) << "UTF-8 text survives";
  EXPECT_EQ(a.at("model_name"), "synthetic_model");
  EXPECT_EQ(a.at("model_source"), "models/synthetic_model.yaml");
  EXPECT_EQ(a.at("model_text"), r.profile().model.text) << "UTF-8 text survives";
  EXPECT_EQ(a.at("integrator"), "rkmk-rkf78");
  EXPECT_NE(a.at("integrator_settings").find("rtol=1e-11"), std::string::npos)
      << a.at("integrator_settings");
  EXPECT_NE(a.at("integrator_settings").find("atol=1e-13"), std::string::npos);
  EXPECT_NE(a.at("integrator_settings").find("output_dt=0.25"), std::string::npos);
  EXPECT_EQ(a.at("mode"), "geometry");
  EXPECT_EQ(a.at("coupling"), "exact");
  EXPECT_EQ(a.at("termination"), integrators::ToString(integrators::Termination::kReachedEnd));
  EXPECT_EQ(a.at("termination_message"), "reached the end");
  EXPECT_NE(a.at("statistics").find("steps=123"), std::string::npos) << a.at("statistics");
  EXPECT_EQ(a.at("max_h_N_drift"), "1.5e-14");
}

std::string FileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

TEST_F(TrajectoryFileTest, StoredProfileAndModelTextsReproduceTheRun) {
  // The main job (a hinged model, exact coupling): write its trajectory, rebuild the
  // profile and model files from the file's two texts alone (the model at the path the
  // profile names, relative to the profile), run again: the same trajectory, bit for bit.
  const std::string source =
      std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/smallsat_three_stage.yaml";
  const MissionResult r = run::RunMission(LoadProfile(source));
  WriteTrajectoryFile(Path("run.h5"), r);
  const TrajectoryFile f = ReadTrajectoryFile(Path("run.h5"));
  const std::map<std::string, std::string>& a = f.attributes;
  EXPECT_EQ(a.at("profile_text"), FileText(source));
  EXPECT_EQ(a.at("model_text"),
            FileText(std::string(DEPLOYSIM_SOURCE_DIR) + "/models/smallsat.yaml"));
  ASSERT_NE(a.at("model_text").find("kind: hinged"), std::string::npos);
  // The run's stage analysis and danger windows, as `analyze` reports them.
  ASSERT_EQ(f.stages.size(), r.stages.size());
  for (std::size_t i = 0; i < r.stages.size(); ++i) {
    EXPECT_EQ(f.stages[i].regime, r.stages[i].regime) << i;
    EXPECT_EQ(f.stages[i].separatrix_distance, r.stages[i].separatrix_distance) << i;
    EXPECT_EQ(f.stages[i].observed_flip_count,
              static_cast<long long>(r.stages[i].observed_flips.size()))
        << i;
  }
  EXPECT_GT(f.stages.back().observed_flip_count, 0);
  EXPECT_EQ(f.stages.back().spin_axis_role, "intermediate");
  ASSERT_EQ(f.danger_windows.size(), r.danger_windows.size());
  ASSERT_FALSE(f.danger_windows.empty());
  EXPECT_EQ(f.danger_windows.back().t_end, r.danger_windows.back().t_end);

  const fs::path profile_dir = fs::path(a.at("profile_source")).parent_path();
  const fs::path model_relative = fs::relative(a.at("model_source"), profile_dir);
  const fs::path rerun_profile = fs::path(Path("profiles")) / "rerun.yaml";
  fs::create_directories(rerun_profile.parent_path());
  fs::create_directories((rerun_profile.parent_path() / model_relative).parent_path());
  std::ofstream(rerun_profile, std::ios::binary) << a.at("profile_text");
  std::ofstream(rerun_profile.parent_path() / model_relative, std::ios::binary)
      << a.at("model_text");
  const MissionResult again = run::RunMission(LoadProfile(rerun_profile.string()));
  ExpectSameTrajectory(r.trajectory, again.trajectory);
  EXPECT_EQ(again.flip_times, r.flip_times);
  EXPECT_FALSE(r.flip_times.empty()) << "the main job tumbles once deployed";
}

TEST_F(TrajectoryFileTest, EveryDatasetHasUnits) {
  const std::string path = Path("out.h5");
  WriteTrajectoryFile(path, SyntheticResult(schedule::Mode::kGeometry));
  const std::map<std::string, std::string> expected = {
      {"/time", "s"},
      {"/H_B", "kg m^2/s"},
      {"/w_NB_B", "rad/s"},
      {"/q_NB", "1"},
      {"/J_B", "kg m^2"},
      {"/principal_moments", "kg m^2"},
      {"/h_rel_B", "kg m^2/s"},
      {"/h_N", "kg m^2/s"},
      {"/energy", "J"},
      {"/energy_rigid", "J"},
      {"/euler_313", "rad"},
      {"/spin_axis_angle", "rad"},
      {"/work_damper", "J"},
      {"/work_friction", "J"},
      {"/work_motor", "J"},
      {"/work_drive", "J"},
      {"/work_impacts", "J"},
      {"/hinge_angles", "rad"},
      {"/hinge_rates", "rad/s"},
      {"/energy_spring", "J"},
      {"/energy_total", "J"},
      {"/panel_names", "none"},
      {"/hinge_latch_time", "s"},
      {"/events/flip_time", "s"},
      {"/events/predicted_flip_time", "s"},
      {"/events/spin_axis_45_time", "s"},
      {"/events/hinge/time", "s"},
      {"/events/hinge/panel", "1"},
      {"/events/hinge/panel_name", "none"},
      {"/events/hinge/kind", "none"},
      {"/events/hinge/angle", "rad"},
      {"/events/hinge/rate_before", "rad/s"},
      {"/events/hinge/rate_after", "rad/s"},
      {"/events/hinge/impulse", "N m s"},
      {"/events/hinge/w_jump_B", "rad/s"},
      {"/events/hinge/energy_dissipated", "J"},
      {"/events/hinge/drive_work", "J"},
      {"/stages/caveat", "none"},
      {"/stages/rigid_body_only", "1"},
      {"/danger_windows/t_begin", "s"},
      {"/danger_windows/t_end", "s"},
      {"/stages/index", "1"},
      {"/stages/rigid", "1"},
      {"/stages/moments_end", "kg m^2"},
      {"/stages/spin_axis_role", "none"},
      {"/stages/regime", "none"},
      {"/stages/one_minus_k2", "1"},
      {"/stages/separatrix_distance", "1"},
      {"/stages/predicted_flip_half_period", "s"},
      {"/stages/predicted_flip_count", "1"},
      {"/stages/observed_flip_count", "1"},
      {"/stages/max_flip_time_difference", "s"},
      {"/stages/t_begin", "s"},
      {"/stages/t_end", "s"},
      {"/stages/name", "none"},
      {"/stages/law", "none"},
      {"/stages/from", "none"},
      {"/stages/to", "none"},
  };
  EXPECT_EQ(ReadTrajectoryFile(path).units, expected);
}

TEST_F(TrajectoryFileTest, TensorModeHasNoHingeAngles) {
  const MissionResult r = SyntheticResult(schedule::Mode::kTensor);
  const std::string path = Path("tensor.h5");
  WriteTrajectoryFile(path, r);
  const TrajectoryFile f = ReadTrajectoryFile(path);
  ExpectSameTrajectory(r.trajectory, f.trajectory);
  EXPECT_TRUE(f.trajectory.hinge_angles.empty());
  EXPECT_TRUE(f.trajectory.hinge_rates.empty());
  EXPECT_TRUE(f.panel_names.empty());
  EXPECT_EQ(f.units.count("/hinge_angles"), 0u);
  EXPECT_EQ(f.units.count("/hinge_rates"), 0u);
  EXPECT_EQ(f.units.count("/panel_names"), 0u);
  // The per-sample energies and the event tables are there in tensor mode too.
  EXPECT_EQ(f.units.count("/energy_total"), 1u);
  ExpectSameHingeOutputs(r, f);
  EXPECT_EQ(f.attributes.at("mode"), "tensor");
}

TEST_F(TrajectoryFileTest, NoFlipsAndNoSamples) {
  MissionResult r = SyntheticResult(schedule::Mode::kTensor);
  r.flip_times.clear();
  r.trajectory = run::Trajectory();
  const std::string path = Path("empty.h5");
  WriteTrajectoryFile(path, r);
  const TrajectoryFile f = ReadTrajectoryFile(path);
  EXPECT_EQ(f.trajectory.size(), 0u);
  EXPECT_TRUE(f.flip_times.empty());
  EXPECT_EQ(f.stages.size(), 2u);
}

TEST_F(TrajectoryFileTest, H5dumpReadsTheFile) {
  if (!HaveH5dump()) GTEST_SKIP() << "h5dump not installed";
  const std::string path = Path("out.h5");
  WriteTrajectoryFile(path, SyntheticResult(schedule::Mode::kGeometry));
  EXPECT_EQ(std::system(("h5dump -H '" + path + "' > /dev/null 2>&1").c_str()), 0);
  const std::string header = Capture("h5dump -H '" + path + "'");
  EXPECT_NE(header.find("DATASET \"J_B\""), std::string::npos) << header;
  EXPECT_NE(header.find("( 7, 3, 3 )"), std::string::npos) << "J_B is N x 3 x 3";
  EXPECT_NE(header.find("( 7, 4 )"), std::string::npos) << "q_NB is N x 4";
  EXPECT_NE(header.find("( 7, 2 )"), std::string::npos) << "hinge_angles is N x P";
  EXPECT_NE(header.find("GROUP \"events\""), std::string::npos);
  EXPECT_NE(header.find("ATTRIBUTE \"units\""), std::string::npos);
  const std::string units = Capture("h5dump -a /H_B/units '" + path + "'");
  EXPECT_NE(units.find("\"kg m^2/s\""), std::string::npos) << units;
  const std::string q = Capture("h5dump -d /stages/law '" + path + "'");
  EXPECT_NE(q.find("\"minimum-jerk\""), std::string::npos) << q;
}

TEST_F(TrajectoryFileTest, OverwritesAnExistingFileAndLeavesNoTemporary) {
  const std::string path = Path("out.h5");
  WriteTrajectoryFile(path, SyntheticResult(schedule::Mode::kTensor));
  WriteTrajectoryFile(path, SyntheticResult(schedule::Mode::kGeometry));
  EXPECT_EQ(ReadTrajectoryFile(path).attributes.at("mode"), "geometry");
  EXPECT_EQ(Entries(), std::vector<std::string>{"out.h5"});
}

TEST_F(TrajectoryFileTest, MissingDirectoryLeavesNothing) {
  const std::string path = Path("no_such_dir/out.h5");
  EXPECT_THROW(WriteTrajectoryFile(path, SyntheticResult(schedule::Mode::kTensor)),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(Entries().empty());
}

TEST_F(TrajectoryFileTest, UnwritableDirectoryLeavesNothing) {
  // A regular file as the "directory": nothing can be created in it, even as root.
  Write("not_a_dir", "x");
  const std::string path = Path("not_a_dir/out.h5");
  try {
    WriteTrajectoryFile(path, SyntheticResult(schedule::Mode::kTensor));
    FAIL() << "wrote into a file";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
  }
  EXPECT_EQ(Entries(), std::vector<std::string>{"not_a_dir"});
}

TEST_F(TrajectoryFileTest, FailedRenameRemovesTheTemporary) {
  // The contents are written completely, then the rename onto a directory fails.
  fs::create_directory(Path("taken"));
  EXPECT_THROW(WriteTrajectoryFile(Path("taken"), SyntheticResult(schedule::Mode::kGeometry)),
               std::runtime_error);
  EXPECT_TRUE(fs::is_directory(Path("taken")));
  EXPECT_EQ(Entries(), std::vector<std::string>{"taken"});
}

TEST_F(TrajectoryFileTest, InconsistentTrajectoryIsRejectedAndTheOldFileKept) {
  const std::string path = Path("out.h5");
  WriteTrajectoryFile(path, SyntheticResult(schedule::Mode::kTensor));
  MissionResult bad = SyntheticResult(schedule::Mode::kGeometry);
  bad.trajectory.energy.pop_back();
  EXPECT_THROW(WriteTrajectoryFile(path, bad), std::invalid_argument);
  bad = SyntheticResult(schedule::Mode::kGeometry);
  bad.trajectory.hinge_angles[3] = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(WriteTrajectoryFile(path, bad), std::invalid_argument);
  bad = SyntheticResult(schedule::Mode::kGeometry);
  bad.trajectory.hinge_rates.pop_back();
  EXPECT_THROW(WriteTrajectoryFile(path, bad), std::invalid_argument);
  bad = SyntheticResult(schedule::Mode::kGeometry);
  bad.trajectory.hinge_rates[2] = Eigen::VectorXd::Zero(1);
  EXPECT_THROW(WriteTrajectoryFile(path, bad), std::invalid_argument);
  bad = SyntheticResult(schedule::Mode::kTensor);
  bad.trajectory.energy_spring.clear();
  EXPECT_THROW(WriteTrajectoryFile(path, bad), std::invalid_argument);
  bad = SyntheticResult(schedule::Mode::kTensor);
  bad.latch_times.push_back(1.0);  // three latch times, two panels
  EXPECT_THROW(WriteTrajectoryFile(path, bad), std::invalid_argument);
  bad = SyntheticResult(schedule::Mode::kTensor);
  bad.hinge_events[1].panel = kPanels;
  try {
    WriteTrajectoryFile(path, bad);
    ADD_FAILURE() << "an event of panel " << kPanels << " was written";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("panel = 2 (rule: in [0, 2))"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(ReadTrajectoryFile(path).attributes.at("mode"), "tensor");
  EXPECT_EQ(Entries(), std::vector<std::string>{"out.h5"});
}

TEST_F(TrajectoryFileTest, ReadingBadFilesThrowsRuntimeError) {
  EXPECT_THROW((void)ReadTrajectoryFile(Path("missing.h5")), std::runtime_error);
  const std::string text = Write("text.h5", "not hdf5\n");
  try {
    (void)ReadTrajectoryFile(text);
    FAIL() << "read a text file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not an HDF5 file"), std::string::npos) << e.what();
  }
}

// ---- CSV ----

TEST(TrajectorySchemaDocs, FileFormatsListsEveryColumnWithShapeAndUnits) {
  std::ifstream in(std::string(DEPLOYSIM_SOURCE_DIR) + "/docs/file_formats.md");
  ASSERT_TRUE(in);
  std::stringstream text;
  text << in.rdbuf();
  for (const run::TrajectoryColumn& c : run::TrajectorySchema::Standard().columns()) {
    std::string shape = "N";
    if (c.shape == run::ColumnShape::kPerPanel) {
      shape += "×P";
    } else {
      for (std::size_t d : run::RowShape(c, 0)) shape += "×" + std::to_string(d);
    }
    const std::string row = "| `/" + c.name + "` | " + shape + " | " + c.units + " |";
    EXPECT_NE(text.str().find(row), std::string::npos) << row;
  }
}

// docs/file_formats.md ("The outcome") explains every member of the outcome record, the
// nested ones included.
TEST(TrajectorySchemaDocs, FileFormatsExplainsEveryMemberOfTheOutcome) {
  std::ifstream in(std::string(DEPLOYSIM_SOURCE_DIR) + "/docs/file_formats.md");
  ASSERT_TRUE(in);
  std::stringstream text;
  text << in.rdbuf();
  const std::size_t begin = text.str().find("### The outcome");
  ASSERT_NE(begin, std::string::npos);
  const std::string section = text.str().substr(begin, text.str().find("\n## ", begin) - begin);
  analysis::MotionOutcome o;
  o.faults.emplace_back();
  const std::string json = analysis::OutcomeJson(o);
  int members = 0;
  for (std::size_t at = json.find('"'); at != std::string::npos;
       at = json.find('"', json.find('"', at + 1) + 1)) {
    const std::size_t end = json.find('"', at + 1);
    if (json.compare(end + 1, 1, ":") != 0) continue;  // a value, not a name
    const std::string name = json.substr(at + 1, end - at - 1);
    EXPECT_NE(section.find("`" + name + "`"), std::string::npos) << name;
    ++members;
  }
  EXPECT_GT(members, 40);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
