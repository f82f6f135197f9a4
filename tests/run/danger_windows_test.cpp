// The danger window table: its columns in file order with their units, each giving and
// taking its window's value, and one column of a name.

#include "deploysim/run/danger_windows.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

TEST(DangerWindowsTest, ColumnsGiveAndTakeTheWindowsValues) {
  const std::vector<DangerWindowColumn>& cols = DangerWindowTable::Columns();
  ASSERT_GE(cols.size(), 2u);
  EXPECT_EQ(cols[0].name, "t_begin");
  EXPECT_EQ(cols[1].name, "t_end");
  const DangerWindow w{12.5, 40.25};
  DangerWindow back;
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(cols[i].units, "s");
    ASSERT_TRUE(cols[i].set);
    cols[i].set(back, cols[i].value(w));
  }
  EXPECT_EQ(back.t_begin, 12.5);
  EXPECT_EQ(back.t_end, 40.25);
}

TEST(DangerWindowsTest, AColumnNameIsTakenOnce) {
  DangerWindowColumn c;
  c.name = "t_end";
  EXPECT_THROW(DangerWindowTable::Extend(c), std::logic_error);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
