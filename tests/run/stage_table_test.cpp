// The stage table's rows (run::StageRows): a stage profile's stages as the profile states
// them with their reports, a hinge profile's phases without configurations; the table
// refuses a second column of a name.

#include "deploysim/run/stage_table.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "run/hinge_fixtures.h"
#include "run/stage_fixtures.h"

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

/// A deployment, then a hold spinning about y, the deployed body's intermediate axis.
schedule::Profile TwoStages() {
  using schedule::Law;
  using testing::MakeStage;
  schedule::Profile p = testing::TwoShapeProfile(
      "two stages", math::Vec3(0.01, 1.0, 0.02),
      {MakeStage("deploy", "stowed", "deployed", Law::kSmoothstep, 0.0, 5.0),
       MakeStage("deployed", "deployed", "deployed", Law::kStep, 5.0, 120.0)});
  p.output.dt = 1.0;
  return p;
}

TEST(StageTableTest, AStageProfilesRowsAreItsStagesWithTheirReports) {
  const MissionResult r = RunMission(TwoStages());
  const std::vector<StageRow> rows = StageRows(r);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].name, "deploy");
  EXPECT_EQ(rows[0].law, "smoothstep");
  EXPECT_EQ(rows[0].from, "stowed");
  EXPECT_EQ(rows[0].to, "deployed");
  EXPECT_FALSE(rows[0].rigid);
  EXPECT_EQ(rows[1].law, "hold");
  EXPECT_EQ(rows[1].t_begin, 5.0);
  EXPECT_EQ(rows[1].t_end, 120.0);
  EXPECT_TRUE(rows[1].rigid);
  // Each row's analysis is its report's.
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].index, static_cast<int>(i));
    EXPECT_EQ(rows[i].spin_axis_role, analysis::ToString(r.stages[i].spin_axis_end));
    EXPECT_EQ(rows[i].observed_flip_count,
              static_cast<long long>(r.stages[i].observed_flips.size()));
    EXPECT_EQ(rows[i].observed_flips, r.stages[i].observed_flips);
    EXPECT_EQ(rows[i].moments_end, r.stages[i].moments_end);
  }
}

TEST(StageTableTest, AHingeProfilesRowsArePhasesWithoutConfigurations) {
  const MissionResult r = RunMission(testing::SmallsatHingeProfile(
      testing::SpringHinge(0.2, -30.0), testing::SpringHinge(0.15, -20.0), 100.0));
  const std::vector<StageRow> rows = StageRows(r);
  ASSERT_EQ(rows.size(), r.stages.size());
  ASSERT_GE(rows.size(), 1u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].name, r.stages[i].name);
    EXPECT_EQ(rows[i].t_begin, r.stages[i].t_begin);
    EXPECT_TRUE(rows[i].from.empty());
    EXPECT_TRUE(rows[i].to.empty());
  }
  // Where a column does not apply: a phase's configurations.
  for (const StageColumn& c : StageTable::Columns()) {
    if (c.name == "from" || c.name == "to") {
      ASSERT_TRUE(c.applies);
      EXPECT_FALSE(c.applies(rows[0]));
    }
  }
}

TEST(StageTableTest, AColumnNameIsTakenOnce) {
  StageColumn c;
  c.name = "t_begin";
  EXPECT_THROW(StageTable::Extend(c), std::logic_error);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
