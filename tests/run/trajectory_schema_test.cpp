// run::TrajectorySchema: the one list of the trajectory's columns, its rules and
// the bookkeeping derived from it.

#include "deploysim/run/trajectory_schema.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <set>
#include <stdexcept>
#include <string>

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

/// n samples with distinct values in every member, `panels` hinge values each.
Trajectory Samples(std::size_t n, std::size_t panels) {
  Trajectory t;
  for (std::size_t k = 0; k < n; ++k) {
    const double x = static_cast<double>(k) + 0.25;
    t.time.push_back(x);
    t.H_B.emplace_back(x, 2 * x, 3 * x);
    t.w_NB_B.emplace_back(-x, x, 0.5);
    t.q_NB.push_back(math::Quat(Eigen::AngleAxisd(x, math::Vec3::UnitZ())));
    math::Mat3 J;
    J << 1, 2, 3, 2, 5, 6, 3, 6, 9 + x;
    t.J_B.push_back(J);
    t.principal_moments.emplace_back(1, 2, 3 + x);
    t.h_rel_B.emplace_back(0.1, 0.2, x);
    t.h_N.emplace_back(x, 0, 1);
    t.energy.push_back(4 * x);
    t.energy_rigid.push_back(3 * x);
    t.energy_spring.push_back(x / 8);
    t.euler_313.emplace_back(x, x / 2, x / 3);
    t.spin_axis_angle.push_back(x / 10);
    t.hinge_angles.push_back(Eigen::VectorXd::Constant(static_cast<Eigen::Index>(panels), x));
    t.hinge_rates.push_back(Eigen::VectorXd::Constant(static_cast<Eigen::Index>(panels), -x));
    t.work_damper.push_back(-x);
    t.work_friction.push_back(-x / 2);
    t.work_motor.push_back(x / 3);
    t.work_drive.push_back(x / 4);
    t.work_impacts.push_back(-x / 5);
  }
  return t;
}

TEST(TrajectorySchema, StandardColumnsHaveUniqueNamesAndTimeFirst) {
  const TrajectorySchema& s = TrajectorySchema::Standard();
  ASSERT_FALSE(s.columns().empty());
  EXPECT_EQ(s.columns().front().name, "time");
  std::set<std::string> names;
  for (const TrajectoryColumn& c : s.columns()) {
    EXPECT_TRUE(names.insert(c.name).second) << c.name;
    EXPECT_FALSE(c.units.empty()) << c.name;
    EXPECT_FALSE(c.description.empty()) << c.name;
  }
  EXPECT_EQ(s.Written(false).size() + 2, s.Written(true).size());  // hinge angles, rates
}

TEST(TrajectorySchema, RowValuesRoundTripThroughStorage) {
  const TrajectorySchema& s = TrajectorySchema::Standard();
  const Trajectory t = Samples(3, 2);
  Trajectory back;
  for (const TrajectoryColumn& c : s.columns()) {
    if (!c.storage) continue;
    const std::size_t width = Width(c, 2);
    std::vector<double> row(width);
    for (std::size_t k = 0; k < t.size(); ++k) {
      c.values(t, k, row.data());
      c.storage->push(back, row.data(), width);
    }
  }
  EXPECT_EQ(back.time, t.time);
  EXPECT_EQ(back.J_B, t.J_B);
  EXPECT_EQ(back.hinge_rates, t.hinge_rates);
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_EQ(back.q_NB[k].coeffs(), t.q_NB[k].coeffs());
  }
  // J_B row-major, quaternions scalar first.
  const TrajectoryColumn& J = s.columns()[4];
  ASSERT_EQ(J.name, "J_B");
  double m[9];
  J.values(t, 1, m);
  EXPECT_EQ(m[2], t.J_B[1](0, 2));
  EXPECT_EQ(m[8], t.J_B[1](2, 2));
  const TrajectoryColumn& q = s.columns()[3];
  double wxyz[4];
  q.values(t, 1, wxyz);
  EXPECT_EQ(wxyz[0], t.q_NB[1].w());
}

TEST(TrajectorySchema, AppendClearAndRowKeepEveryMember) {
  const TrajectorySchema& s = TrajectorySchema::Standard();
  const Trajectory a = Samples(3, 1);
  Trajectory all = a;
  s.Append(all, a);
  EXPECT_EQ(all.size(), 6u);
  EXPECT_EQ(all.hinge_rates.size(), 6u);
  EXPECT_EQ(all.euler_313.size(), 6u);
  const Trajectory last = s.Row(all, 5);
  EXPECT_EQ(last.size(), 1u);
  EXPECT_EQ(last.energy_spring, std::vector<double>{a.energy_spring[2]});
  EXPECT_EQ(last.hinge_angles.size(), 1u);
  s.Check("row", last, 1);
  s.Clear(all);
  EXPECT_EQ(all.size(), 0u);
  EXPECT_TRUE(all.hinge_angles.empty());
  EXPECT_TRUE(all.spin_axis_angle.empty());
}

TEST(TrajectorySchema, CheckNamesTheMemberAndTheRule) {
  const TrajectorySchema& s = TrajectorySchema::Standard();
  Trajectory t = Samples(4, 2);
  s.Check("f", t, 2);
  s.Check("f", t, 0);  // per-panel members not checked
  t.energy_rigid.pop_back();
  try {
    s.Check("f.h5", t, 2);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "f.h5: trajectory.energy_rigid has 3 samples, time has 4 (rule: one sample per "
              "output time)");
  }
  t = Samples(4, 2);
  t.hinge_rates[2].resize(1);
  EXPECT_THROW(s.Check("f", t, 2), std::invalid_argument);
  EXPECT_NO_THROW(s.Check("f", t, 0));
}

TEST(TrajectorySchema, AddRejectsWhatTheWritersCouldNotWrite) {
  TrajectorySchema s = TrajectorySchema::Standard();
  TrajectoryColumn c;
  c.name = "time";
  c.values = [](const Trajectory&, std::size_t, double* row) { row[0] = 0; };
  EXPECT_THROW(s.Add(c), std::invalid_argument);  // taken
  c.name = "";
  EXPECT_THROW(s.Add(c), std::invalid_argument);
  c.name = "x";
  c.values = nullptr;
  EXPECT_THROW(s.Add(c), std::invalid_argument);  // no values
  c.values = [](const Trajectory&, std::size_t, double* row) { row[0] = 0; };
  c.shape = ColumnShape::kVector3;
  EXPECT_THROW(s.Add(c), std::invalid_argument);  // no CSV components
  c.csv_components = {"a", "b", "c"};
  c.csv_indices = {0, 1, 3};
  EXPECT_THROW(s.Add(c), std::invalid_argument);  // index outside the row
  c.csv_indices = {0, 1, 2};
  s.Add(c);
  EXPECT_EQ(s.columns().back().csv_prefix, "x");
  EXPECT_EQ(s.columns().size(), TrajectorySchema::Standard().columns().size() + 1);
}

TEST(TrajectorySchema, PanelCountIsTheFirstHingeRowLength) {
  EXPECT_EQ(PanelCount(Samples(2, 3)), 3u);
  EXPECT_EQ(PanelCount(Trajectory{}), 0u);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
