// End-to-end tests of the `deploysim` command: every
// shipped profile runs and its HDF5 file is read back and checked; every malformed
// input of the corpus gives its specific one-line message, a non-zero exit and no
// output file.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/run/mission.h"
#include "deploysim/io/trajectory_file.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/number_format.h"

namespace deploysim {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;

// h_N is constant: the drift of every shipped stage profile, measured 1.2e-15 to 2.1e-15
// (rounding), stays below this.
constexpr double kMomentumTolerance = 1e-14;
// [s] flips inside rigid stages against the closed form: measured 0 to 4.1e-11 (wing_nut).
constexpr double kFlipTolerance = 2e-10;

struct CliRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Runs the CLI with arguments (shell-quoted by the caller), capturing stdout and stderr.
CliRun RunCli(const std::string& args, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt";
  const fs::path err = dir / "stderr.txt";
  const std::string cmd = std::string("'") + DEPLOYSIM_CLI + "' " + args + " >'" + out.string() +
                          "' 2>'" + err.string() + "'";
  const int status = std::system(cmd.c_str());
  CliRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  auto slurp = [](const fs::path& p) {
    std::ifstream f(p);
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  };
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

fs::path TempDir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("deploysim_cli_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(CliTest, HelpAndVersion) {
  const fs::path d = TempDir("help");
  const CliRun help = RunCli("--help", d);
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("Examples:"), std::string::npos) << help.out;
  EXPECT_NE(help.out.find("simulate"), std::string::npos);
  const CliRun version = RunCli("--version", d);
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.out.find("deploysim "), std::string::npos);
  const CliRun none = RunCli("", d);
  EXPECT_NE(none.exit_code, 0);
  fs::remove_all(d);
}

TEST(CliTest, MissingProfileFileIsOneLineError) {
  const fs::path d = TempDir("missing");
  const CliRun r = RunCli(
      "simulate '" + (d / "nope.yaml").string() + "' -o '" + (d / "out.h5").string() + "'", d);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("nope.yaml"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(d / "out.h5"));
  fs::remove_all(d);
}

// Every shipped profile: runs, writes a readable file whose h_N is constant and whose
// flips in constant-inertia stages match the analytic engine started from the file's
// own state at the first output time of the stage.
TEST(CliTest, EveryShippedProfileRunsAndChecksOut) {
  const fs::path d = TempDir("profiles");
  int count = 0;
  for (const auto& entry :
       fs::directory_iterator(fs::path(DEPLOYSIM_SOURCE_DIR) / "deployment_profiles")) {
    if (entry.path().extension() != ".yaml") continue;
    // simulate does not run hinge profiles yet (HingeProfilesAreAnalyzedOrRefused...).
    if (io::LoadProfile(entry.path().string()).is_hinge_profile()) continue;
    ++count;
    const std::string name = entry.path().stem().string();
    SCOPED_TRACE(name);
    const fs::path out = d / (name + ".h5");
    const CliRun r =
        RunCli("simulate '" + entry.path().string() + "' -o '" + out.string() + "'", d);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const io::TrajectoryFile f = io::ReadTrajectoryFile(out.string());
    const run::Trajectory& tr = f.trajectory;
    ASSERT_GT(tr.size(), 2u);
    const math::Vec3 h0 = tr.h_N.front();
    double drift = 0.0;
    for (std::size_t i = 0; i < tr.size(); ++i) {
      drift = std::max(drift, (tr.q_NB[i] * tr.H_B[i] - h0).norm() / h0.norm());
    }
    EXPECT_LE(drift, kMomentumTolerance);
    ::testing::Test::RecordProperty(name + "_h_N_drift", math::FormatNumber(drift));
    double worst_flip = 0.0;
    const math::Vec3 spin_axis = analysis::InitialSpinAxis(tr.J_B.front(), tr.H_B.front());
    for (const io::StageRow& st : f.stages) {
      if (st.law != "hold" && st.law != "step") continue;
      std::size_t i = 0;
      while (i < tr.size() && tr.time[i] <= st.t_begin) ++i;  // strictly inside the stage
      if (i >= tr.size() || tr.time[i] >= st.t_end) continue;
      const analysis::FreeBodySolution sol(math::InertiaTensor::FromMatrix(tr.J_B[i]), tr.H_B[i],
                                           tr.q_NB[i], tr.time[i]);
      // Flips: sign changes along the intermediate axis while it is the spin axis.
      const bool intermediate =
          analysis::LocateSpinAxis(tr.J_B[i], spin_axis).role == analysis::AxisRole::kIntermediate;
      const std::vector<double> predicted =
          intermediate ? sol.FlipTimes(tr.time[i], st.t_end) : std::vector<double>{};
      std::vector<double> observed;
      for (double t : f.flip_times) {
        if (t > tr.time[i] && t < st.t_end) observed.push_back(t);
      }
      ASSERT_EQ(observed.size(), predicted.size()) << "stage " << st.name;
      for (std::size_t k = 0; k < observed.size(); ++k) {
        worst_flip = std::max(worst_flip, std::abs(observed[k] - predicted[k]));
      }
    }
    EXPECT_LE(worst_flip, kFlipTolerance);
    EXPECT_LE(worst_flip, 5e-10);  // [s] measured 1.2e-10: a regression shows
    ::testing::Test::RecordProperty(name + "_max_flip_error_s", math::FormatNumber(worst_flip));
  }
  EXPECT_GE(count, 5);
  fs::remove_all(d);
}

// A hinge profile runs through analyze, simulate (the trajectory with its hinge
// outputs) and crosscheck (against the Simbody model of free hinges).
TEST(CliTest, HingeProfilesRunThroughEveryCommand) {
  const fs::path d = TempDir("hinges");
  const std::string profile =
      (fs::path(DEPLOYSIM_SOURCE_DIR) / "deployment_profiles/smallsat_spring_deploy.yaml").string();
  const CliRun analyzed = RunCli("analyze '" + profile + "'", d);
  EXPECT_EQ(analyzed.exit_code, 0) << analyzed.err;
  EXPECT_NE(analyzed.out.find("deployment timeline"), std::string::npos) << analyzed.out;
  EXPECT_NE(analyzed.out.find("energy ledger: E = T + V from"), std::string::npos) << analyzed.out;
  const fs::path out = d / "out.h5";
  const CliRun simulated = RunCli("simulate '" + profile + "' -o '" + out.string() + "'", d);
  EXPECT_EQ(simulated.exit_code, 0) << simulated.err;
  EXPECT_NE(simulated.out.find("latch"), std::string::npos) << simulated.out;
  EXPECT_TRUE(fs::exists(out));
  const CliRun help = RunCli("--help", d);
  if (help.out.find("crosscheck") != std::string::npos) {
    const fs::path cc = d / "cc.h5";
    const CliRun checked =
        RunCli("crosscheck '" + profile + "' --until 70 -o '" + cc.string() + "'", d);
    EXPECT_EQ(checked.exit_code, 0) << checked.err;
    EXPECT_NE(checked.out.find("Simbody cross-check (free hinges)"), std::string::npos)
        << checked.out;
    EXPECT_NE(checked.out.find("latch times [s]"), std::string::npos) << checked.out;
    EXPECT_NE(checked.out.find("verdict: agree"), std::string::npos) << checked.out;
    EXPECT_TRUE(fs::exists(cc));
    // A tolerance below the two models' difference: they disagree, exit 4, and the
    // comparison is still written (it is the evidence).
    const fs::path strict = d / "strict.h5";
    const CliRun disagree = RunCli(
        "crosscheck '" + profile + "' --until 70 --tolerance 1e-13 -o '" + strict.string() + "'",
        d);
    EXPECT_EQ(disagree.exit_code, 4) << disagree.err;
    EXPECT_NE(disagree.out.find("verdict: DISAGREE: H_B differs by"), std::string::npos)
        << disagree.out;
    EXPECT_TRUE(fs::exists(strict));
  }
  fs::remove_all(d);
}

// The malformed-input corpus of tests/io/bad_inputs through the CLI.
TEST(CliTest, MalformedProfilesFailCleanly) {
  const fs::path d = TempDir("bad");
  int count = 0;
  for (const auto& entry :
       fs::directory_iterator(fs::path(DEPLOYSIM_SOURCE_DIR) / "tests/io/bad_inputs")) {
    if (entry.path().extension() != ".yaml") continue;
    std::ifstream in(entry.path());
    std::string first;
    std::getline(in, first);
    const std::string tag = "# expect: ";
    if (first.rfind(tag, 0) != 0) continue;  // helper files (`# valid`)
    const std::string expected = first.substr(tag.size());
    // Profiles only (files with a `model:` or `stages:` key); model files are covered
    // by the io tests.
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.find("\nmodel:") == std::string::npos && text.find("\nstages:") == std::string::npos &&
        text.rfind("model:", 0) != 0 && text.rfind("stages:", 0) != 0) {
      continue;
    }
    const fs::path out = d / "out.h5";
    const CliRun r =
        RunCli("simulate '" + entry.path().string() + "' -o '" + out.string() + "'", d);
    SCOPED_TRACE(entry.path().filename().string());
    ++count;
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out));
    for (const auto& left : fs::directory_iterator(d)) {
      const std::string n = left.path().filename().string();
      EXPECT_TRUE(n == "stdout.txt" || n == "stderr.txt") << "left behind: " << n;
    }
  }
  EXPECT_GE(count, 15);
  fs::remove_all(d);
}

TEST(CliTest, SweepRunsAndRejectsBadSweepFiles) {
  const fs::path d = TempDir("sweep");
  const std::string src = DEPLOYSIM_SOURCE_DIR;
  const CliRun help = RunCli("--help", d);
  if (help.out.find("sweep") == std::string::npos) GTEST_SKIP() << "built without the sweep module";
  const CliRun ok = RunCli("sweep '" + src + "/sweeps/smallsat_duration_spin.yaml' -q -o '" +
                               (d / "map.h5").string() + "' --csv",
                           d);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_TRUE(fs::exists(d / "map.h5") && fs::exists(d / "map.h5.csv"));
  EXPECT_FALSE(fs::exists(d / "map.h5.partial"));
  std::ofstream(d / "bad.yaml") << "name: bad\nbase: " << src
                                << "/deployment_profiles/smallsat_three_stage.yaml\ngrid:\n  - "
                                   "{parameter: spin_rate_rpm, values: [1, -2]}\n";
  const CliRun bad =
      RunCli("sweep '" + (d / "bad.yaml").string() + "' -o '" + (d / "bad.h5").string() + "'", d);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_EQ(bad.err, "deploysim: error: " + (d / "bad.yaml").string() +
                         ": grid[0].values[1] = -2: spin_rate_rpm must be > 0 [rpm]\n");
  EXPECT_FALSE(fs::exists(d / "bad.h5") || fs::exists(d / "bad.h5.partial"));
  fs::remove_all(d);
}

// An output never replaces an input of the run, nor anything that
// is not a regular file; a self-referencing YAML anchor is an error, not a crash.
TEST(CliTest, OutputNeverReplacesAnInput) {
  const fs::path dir = TempDir("output_over_input");
  fs::copy(fs::path(DEPLOYSIM_SOURCE_DIR) / "deployment_profiles", dir / "deployment_profiles");
  fs::copy(fs::path(DEPLOYSIM_SOURCE_DIR) / "models", dir / "models");
  const fs::path profile = dir / "deployment_profiles" / "wing_nut.yaml";
  const fs::path model = dir / "models" / "wing_nut.yaml";
  const auto size_of = [](const fs::path& p) { return fs::file_size(p); };
  const auto profile_size = size_of(profile);
  const auto model_size = size_of(model);
  for (const fs::path& target : {profile, model}) {
    const CliRun r =
        RunCli("simulate '" + profile.string() + "' -o '" + target.string() + "'", dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("output is the input file"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_EQ(size_of(profile), profile_size);
  EXPECT_EQ(size_of(model), model_size);
  // --csv naming an input through OUT.h5.csv.
  fs::copy_file(profile, dir / "run.h5.csv");
  const CliRun c = RunCli("simulate '" + (dir / "run.h5.csv").string() + "' -q --csv -o '" +
                              (dir / "run.h5").string() + "'",
                          dir);
  EXPECT_EQ(c.exit_code, 1) << c.err;
  EXPECT_FALSE(fs::exists(dir / "run.h5"));
  // Not a regular file.
  const CliRun d = RunCli("simulate '" + profile.string() + "' -q -o /dev/null", dir);
  EXPECT_EQ(d.exit_code, 1) << d.err;
  EXPECT_NE(d.err.find("not a regular file"), std::string::npos) << d.err;
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  fs::remove_all(dir);
}

TEST(CliTest, SelfReferencingAnchorIsAnError) {
  const fs::path dir = TempDir("anchor");
  {
    std::ofstream f(dir / "x.yaml");
    f << "a: &a [*a]\n";
  }
  const CliRun r = RunCli(
      "simulate '" + (dir / "x.yaml").string() + "' -o '" + (dir / "o.h5").string() + "'", dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("an alias refers to a node that contains it"), std::string::npos) << r.err;
  EXPECT_LT(r.err.size(), 300u) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o.h5"));
  fs::remove_all(dir);
}

// A legal but unmeant input runs unchanged, with one warning line per input on stderr,
// the same lines in the file's `warnings` attribute; --until ends the run where it says.
TEST(CliTest, WarningsUntilAndMistypedCommands) {
  const fs::path d = TempDir("warnings");
  std::ifstream in(std::string(DEPLOYSIM_SOURCE_DIR) +
                   "/deployment_profiles/smallsat_spring_deploy.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "release: {at: 60}";
  text.replace(text.find(from), from.size(), "release: {at: 900}");
  text.replace(text.find("model: ../models/"), 17,
               "model: " + std::string(DEPLOYSIM_SOURCE_DIR) + "/models/");
  std::ofstream(d / "late.yaml") << text;
  const CliRun r = RunCli("simulate '" + (d / "late.yaml").string() + "' -q --until 100 -o '" +
                              (d / "late.h5").string() + "'",
                          d);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 2) << r.err;
  EXPECT_EQ(r.err.rfind("deploysim: warning: " + (d / "late.yaml").string() +
                            ": hinges.wing_plus_x.free.release.at = 900: at or after the run's "
                            "end (until = 100 s)",
                        0),
            0u)
      << r.err;
  const io::TrajectoryFile f = io::ReadTrajectoryFile((d / "late.h5").string());
  EXPECT_DOUBLE_EQ(f.trajectory.time.back(), 100.0);
  const std::string json = f.attributes.at("warnings");
  EXPECT_NE(json.find("release.at = 900"), std::string::npos) << json;
  EXPECT_NE(json.find("released at the earliest at 902 s"), std::string::npos) << json;

  const CliRun typo = RunCli("simulat x.yaml", d);
  EXPECT_EQ(typo.exit_code, 1);
  EXPECT_EQ(typo.err,
            "deploysim: error: unknown command 'simulat' (did you mean 'simulate'?) (see "
            "deploysim --help)\n");
  const CliRun sweep = RunCli(
      "simulate '" + std::string(DEPLOYSIM_SOURCE_DIR) + "/sweeps/smallsat_duration_spin.yaml'", d);
  EXPECT_EQ(sweep.exit_code, 1);
  EXPECT_NE(sweep.err.find("this is a sweep file (it has base:), not a deployment profile: run "
                           "it with `deploysim sweep "),
            std::string::npos)
      << sweep.err;
  // A stage profile ends in a hold or is held past its last stage; never inside a move.
  const std::string stage =
      "'" + std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/smallsat_three_stage.yaml'";
  const CliRun inside = RunCli("analyze " + stage + " --until 70", d);
  EXPECT_EQ(inside.exit_code, 1);
  EXPECT_NE(inside.err.find("until = 70 (override): inside the move stage"), std::string::npos)
      << inside.err;
  const CliRun longer = RunCli("analyze " + stage + " --until 700 --json", d);
  EXPECT_EQ(longer.exit_code, 0) << longer.err;
  EXPECT_NE(longer.out.find("\"t_end\": 700"), std::string::npos);
  fs::remove_all(d);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim

namespace deploysim {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

// A wing of its own (spring-deployed, latched) and two beams: the text names each beam
// once instead of its bending hinges (release lines, the locked-panels line, the phase
// names), while the file and --json keep every hinge's release.
TEST(CliTest, SummaryGroupsTheAppendagesBendingHinges) {
  const fs::path d = TempDir("appendages");
  std::ofstream(d / "booms.yaml") << R"(name: booms
kind: hinged
hub: {mass: 50.0, box: [0.8, 0.8, 0.6]}
panels:
  - {name: wing, mass: 2.0, box: [0.6, 0.4, 0.02], hinge_point: [0, 0.4, 0.3],
     hinge_axis: [1, 0, 0], com_offset: [0, 0.3, 0.01]}
appendages:
  - {name: boom_px, kind: beam, root: [0.4, 0, 0], direction: [1, 0, 0], length: 2.0,
     mass_per_length: 0.2, radius: 0.01, bending: [{axis: [0, 1, 0], EI: 20},
     {axis: [0, 0, 1], EI: 20}], damping_ratio: 0.01, segments: 6}
  - {name: boom_mx, kind: beam, root: [-0.4, 0, 0], direction: [-1, 0, 0], length: 2.0,
     mass_per_length: 0.2, radius: 0.01, bending: [{axis: [0, 1, 0], EI: 20}],
     damping_ratio: 0.01, segments: 6}
configurations:
  stowed: {hinge_angles_deg: [-60, 0, 0]}
)";
  std::ofstream(d / "p.yaml") << R"(name: booms
model: booms.yaml
initial: {configuration: stowed, spin: {axis: z, rate_rpm: 10, nutation_deg: 5}}
until: 4
output: {dt: 0.02}
hinges:
  wing:
    free:
      release: {at: 1}
      spring: {stiffness: 2.0, rest_angle_deg: 10}
      latch: {angle_deg: 0}
)";
  const CliRun r =
      RunCli("simulate '" + (d / "p.yaml").string() + "' -o '" + (d / "out.h5").string() + "'", d);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("appendages: boom_px (beam: 6 segments, 2 planes, 12 bending hinges), "
                       "boom_mx (beam: 6 segments, 1 plane, 6 bending hinges)\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("(18 hinges the appendages generated, free from t = 0 s, not listed"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find(" free: boom_px (12), boom_mx (6) "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" free: boom_px (12), boom_mx (6), wing "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("panels locked (latch, jam or rest on a stop): wing "), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("s (latch), boom_px never, boom_mx never\n"), std::string::npos) << r.out;
  // No generated hinge is named anywhere in the text; the wing's own events are listed.
  EXPECT_EQ(r.out.find("boom_px_1"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("boom_mx_1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  wing        release"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  wing        latch"), std::string::npos) << r.out;
  // The file keeps every release, and the stage names with every hinge.
  const io::TrajectoryFile f = io::ReadTrajectoryFile((d / "out.h5").string());
  const auto releases =
      std::count_if(f.hinge_events.begin(), f.hinge_events.end(), [](const io::HingeEventRow& e) {
        return e.event.kind == run::HingeEvent::Kind::kRelease;
      });
  EXPECT_EQ(releases, 18 + 1);
  ASSERT_FALSE(f.stages.empty());
  EXPECT_NE(f.stages.front().name.find("boom_px_1a, boom_px_1b"), std::string::npos);
  EXPECT_EQ(f.attributes.count("body"), 1u);
  fs::remove_all(d);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim
