// The reports of `deploysim simulate` and `analyze` (cli/report.h) for free-hinge runs
// built in C++: the deployment timeline, the per-stage caveats and the JSON;
// and the stage-profile table, unchanged but for the caveat lines.

#include "deploysim/cli/report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "run/hinge_fixtures.h"
#include "deploysim/run/mission.h"
#include "deploysim/math/number_format.h"

namespace deploysim::cli {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using run::HingeEvent;
using run::MissionResult;

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream s(text);
  std::string line;
  while (std::getline(s, line)) lines.push_back(line);
  return lines;
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// The small satellite's wings on latched springs, the second released 2 s after the
/// first latches; a stop with restitution on the second wing's far side.
MissionResult SequencedLatchRun() {
  schedule::HingePlan plus = testing::SpringHinge(0.2, -30.0);
  plus.drive.latch.enabled = true;
  plus.drive.latch.angle = 0.0;
  schedule::HingePlan minus = plus;
  minus.drive.release.kind = schedule::Release::Kind::kAfterLatch;
  minus.drive.release.panel = 0;
  minus.drive.release.delay = 2.0;
  schedule::Profile p = testing::SmallsatHingeProfile(plus, minus, 40.0);
  p.integrator.rtol = 1e-10;
  const MissionResult r = run::RunMission(p);
  EXPECT_EQ(r.termination, integrators::Termination::kReachedEnd) << r.message;
  return r;
}

TEST(ReportTest, TimelineHasOneLinePerHingeEventAndTheLatchTimes) {
  const MissionResult r = SequencedLatchRun();
  ASSERT_EQ(r.hinge_events.size(), 4u);  // release, latch, release, latch
  const std::string timeline = FormatTimeline(r);
  std::printf("%s\n", timeline.c_str());
  const std::vector<std::string> lines = Lines(timeline);
  // Title, two header lines, one line per event, then the totals.
  ASSERT_GE(lines.size(), 3 + r.hinge_events.size() + 3);
  EXPECT_EQ(lines[0], "deployment timeline (hinge events):");
  EXPECT_TRUE(Contains(lines[1], "t [s]") && Contains(lines[1], "impulse") &&
              Contains(lines[1], "|hub w jump|") && Contains(lines[1], "dissipated"))
      << lines[1];
  EXPECT_TRUE(Contains(lines[2], "[deg]") && Contains(lines[2], "[N m s]") &&
              Contains(lines[2], "[J]"))
      << lines[2];
  const char* kinds[] = {"release", "latch", "release", "latch"};
  const char* panels[] = {"wing_plus_x", "wing_plus_x", "wing_minus_x", "wing_minus_x"};
  for (std::size_t i = 0; i < r.hinge_events.size(); ++i) {
    const HingeEvent& e = r.hinge_events[i];
    std::istringstream row(lines[3 + i]);
    std::string t, panel, kind, angle, before, after, impulse, jump, dissipated;
    row >> t >> panel >> kind >> angle >> before >> after >> impulse >> jump >> dissipated;
    SCOPED_TRACE(lines[3 + i]);
    EXPECT_EQ(panel, panels[i]);
    EXPECT_EQ(kind, kinds[i]);
    EXPECT_NEAR(std::stod(t), e.t, 1e-5 * e.t);  // 6 significant digits
    EXPECT_NEAR(std::stod(angle), e.angle * 180 / M_PI, 1e-4);
    if (e.kind == HingeEvent::Kind::kRelease) {
      EXPECT_EQ(before, "-");
      EXPECT_EQ(impulse, "-");
      EXPECT_EQ(dissipated, "-");
      continue;
    }
    EXPECT_NEAR(std::stod(before), e.rate_before * 180 / M_PI,
                1e-5 * std::abs(e.rate_before * 180 / M_PI));
    EXPECT_EQ(std::stod(after), 0.0);
    EXPECT_NEAR(std::stod(impulse), e.impulse, 1e-5 * std::abs(e.impulse));
    EXPECT_NEAR(std::stod(jump), e.w_jump_B.norm() * 180 / M_PI,
                1e-5 * e.w_jump_B.norm() * 180 / M_PI);
    EXPECT_GT(std::stod(jump), 0.0);
    EXPECT_NEAR(std::stod(dissipated), e.energy_dissipated, 1e-5 * e.energy_dissipated);
  }
  char locked[200];
  std::snprintf(locked, sizeof(locked),
                "panels locked (latch, jam or rest on a stop): wing_plus_x %.6g s (latch), "
                "wing_minus_x %.6g s (latch)",
                r.latch_times[0], r.latch_times[1]);
  EXPECT_TRUE(Contains(timeline, locked)) << locked;
  EXPECT_TRUE(Contains(timeline, "energy dissipated in the events: "));
}

TEST(ReportTest, TimelineOfAPanelThatNeverLatches) {
  schedule::HingePlan plus = testing::SpringHinge(0.2, -30.0);
  plus.drive.stops.min_angle = -2 * testing::kDeg;
  plus.drive.stops.restitution = 0.5;
  const MissionResult r =
      run::RunMission(testing::SmallsatHingeProfile(plus, schedule::HingePlan{}, 60.0));
  const std::string timeline = FormatTimeline(r);
  int stops = 0;
  for (const std::string& line : Lines(timeline)) stops += Contains(line, " stop ") ? 1 : 0;
  EXPECT_GE(stops, 3) << timeline;
  EXPECT_TRUE(Contains(timeline, " rest ")) << timeline;
  EXPECT_TRUE(Contains(timeline, "(rest), wing_minus_x never")) << timeline;
}

TEST(ReportTest, StageProfilesHaveNoTimeline) {
  MissionResult r = SequencedLatchRun();
  schedule::Profile stage_profile = r.profile();
  stage_profile.hinges.clear();
  r.run = run::CompiledRun::Uncompiled(stage_profile);
  r.hinge_events.clear();
  EXPECT_EQ(FormatTimeline(r), "");
}

TEST(ReportTest, SummaryListsThePhasesAndTheirCaveats) {
  const MissionResult r = SequencedLatchRun();
  const std::string summary = FormatSummary(r);
  std::printf("%s\n", summary.c_str());
  // Phase names are not cut at 18 characters.
  EXPECT_TRUE(Contains(summary, " free: wing_plus_x ")) << summary;
  EXPECT_TRUE(Contains(summary, "(free hinges)")) << summary;
  EXPECT_TRUE(Contains(summary,
                       "caveats (what each stage's verdict assumes; ! = holds only "
                       "for a perfectly rigid body):"));
  // Every caveat of the run appears, under the table.
  for (const run::StageReport& s : r.stages) {
    EXPECT_TRUE(Contains(summary, s.caveat)) << s.caveat;
  }
  EXPECT_LT(summary.find(" free: wing_plus_x "), summary.find("caveats ("));
  EXPECT_LT(summary.find("caveats ("), summary.find("flips located"));
}

/// A stage profile's result, built by hand so that the text is fixed.
MissionResult StageResult() {
  MissionResult r;
  schedule::Profile p;
  p.name = "demo";
  p.source = "demo.yaml";
  p.model.name = "sat";
  p.integrator.method = "rkf78";
  r.run = run::CompiledRun::Uncompiled(p);
  r.stats.steps = 10;
  r.stats.rejected = 1;
  r.stats.evaluations = 130;
  r.wall_seconds = 0.5;
  r.message = "reached the end time";
  run::StageReport a;
  a.index = 0;
  a.name = "stowed spin";
  a.law = "hold";
  a.t_begin = 0.0;
  a.t_end = 60.0;
  a.rigid = true;
  a.spin_axis_end = analysis::AxisRole::kMinor;
  a.regime = "minor-axis";
  a.one_minus_k2 = 0.5;
  a.separatrix_distance = -0.25;
  a.predicted_flip_half_period = std::numeric_limits<double>::infinity();
  run::SetRigidBodyCaveat(a, false);
  run::StageReport b = a;
  b.index = 1;
  b.name = "deploy";
  b.law = "minimum-jerk";
  b.t_begin = 60.0;
  b.t_end = 80.0;
  b.rigid = false;
  b.regime.clear();
  b.spin_axis_end = analysis::AxisRole::kMajor;
  run::SetRigidBodyCaveat(b, false);
  r.stages = {a, b};
  r.max_h_N_drift = 1e-15;
  return r;
}

// The stage table of a stage profile, with its legend; the caveats follow it.
TEST(ReportTest, StageProfileSummaryIsTheOldTablePlusCaveats) {
  const std::string expected =
      "deploysim analysis of 'demo' (demo.yaml; model 'sat', mode tensor, coupling "
      "quasi-rigid)\n"
      "integrator rkf78: 10 steps, 1 rejected, 130 rhs evaluations, 0.5 s wall; reached the "
      "end time\n"
      "\n"
      " #  stage              law              t0 [s]    t1 [s]  spin axis     polhode about "
      "  1-k^2 [-] sep. dist. [-] flip every [s]     flips\n"
      " 0  stowed spin        hold                  0        60  minor         minor-axis    "
      "        0.5          -0.25            inf       0/0\n"
      " 1  deploy             minimum-jerk         60        80  major         (deploying)   "
      "          -          -0.25              -         0\n"
      "\n"
      "(spin axis: role of the body spin axis among the principal axes at the stage end;\n"
      " polhode about: the principal axis the angular velocity circulates about in the body "
      "(D < I2: minor, D > I2: major);\n"
      " an intermediate spin axis on a minor- or major-axis polhode is a spin that flips;\n"
      " 1-k^2: complementary elliptic parameter, 0 on the separatrix; flips: "
      "observed/predicted for constant stages;\n"
      " sep. dist.: (D - I2)/(I3 - I1), 0 on the separatrix, < 0 circulating about the minor "
      "axis)\n"
      "\n"
      "caveats (what each stage's verdict assumes; ! = holds only for a perfectly rigid body):\n"
      "! 0      minor-axis spin: stable only for a perfectly rigid body; any energy dissipation "
      "(flexible panels, dampers, fuel) drives it into a flat spin about the major axis "
      "(Explorer 1, 1958)\n"
      "  1      major-axis spin: stable, also with energy dissipation\n"
      "\n"
      "flips located: 0\n"
      "danger windows (spin axis = intermediate axis): none\n"
      "invariants: max |h_N(t) - h_N(0)|/|h_N| = 1e-15\n"
      "energy ledger: E = T + V from 0 to 0 J; work done on the system: none; unaccounted 0 J\n";
  EXPECT_EQ(FormatSummary(StageResult()), expected);
}

/// Whether /usr/bin/python3 parses `json` (skipped: true when there is no python3).
bool ParsesAsJson(const std::string& json, std::string& error) {
  if (std::system("/usr/bin/python3 -c pass > /dev/null 2>&1") != 0) return true;
  const std::string path = ::testing::TempDir() + "report_test.json";
  std::ofstream(path) << json;
  const std::string cmd =
      "/usr/bin/python3 -c 'import json,sys; json.load(open(sys.argv[1]))' '" + path + "' 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  char buf[512];
  while (pipe != nullptr && std::fgets(buf, sizeof(buf), pipe) != nullptr) error += buf;
  const int status = pipe != nullptr ? ::pclose(pipe) : -1;
  std::remove(path.c_str());
  return status == 0;
}

TEST(ReportTest, JsonHasCaveatsHingeEventsAndLatchTimes) {
  const MissionResult r = SequencedLatchRun();
  const std::string json = FormatJson(r, nullptr);
  std::string error;
  EXPECT_TRUE(ParsesAsJson(json, error)) << error << json;
  EXPECT_TRUE(Contains(json, "\"caveat\": \"")) << json;
  EXPECT_TRUE(Contains(json, "\"rigid_body_only\": ")) << json;
  EXPECT_TRUE(Contains(json, "\"panel_name\": \"wing_minus_x\", \"kind\": \"latch\""));
  EXPECT_TRUE(Contains(json, "\"kind\": \"release\""));
  // JSON numbers: the shortest text that reads back as the same double.
  const std::string latch =
      "\"latch_times\": {\"wing_plus_x\": " + math::FormatNumber(r.latch_times[0]) +
      ", \"wing_minus_x\": " + math::FormatNumber(r.latch_times[1]) + "}";
  EXPECT_TRUE(Contains(json, latch)) << latch << "\n" << json;
  EXPECT_EQ(std::stod(math::FormatNumber(r.latch_times[1])), r.latch_times[1]);
  EXPECT_TRUE(Contains(json, "\"spin_axis_45_crossings\": ["));

  // A stage profile: the same keys, empty.
  const std::string stage_json = FormatJson(StageResult(), nullptr);
  EXPECT_TRUE(ParsesAsJson(stage_json, error)) << error << stage_json;
  EXPECT_TRUE(Contains(stage_json, "\"hinge_events\": []"));
  EXPECT_TRUE(Contains(stage_json, "\"latch_times\": {}"));
  EXPECT_TRUE(Contains(stage_json, "\"spin_axis_45_crossings\": []"));
  EXPECT_TRUE(Contains(stage_json,
                       "\"caveat\": \"major-axis spin: stable, also with energy "
                       "dissipation\", \"rigid_body_only\": false"));
}

TEST(ReportTest, JsonWritesNeverLatchedAsNull) {
  MissionResult r = SequencedLatchRun();
  r.latch_times[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(Contains(FormatJson(r, nullptr), "\"wing_minus_x\": null}"));
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::cli
