// Sweep progress (sweep/progress.h): the durations' format, the plain lines of a log
// (at the interval, the cases counted, the percentage), the bar on a terminal (its
// filling, redrawn in place and cleared) and the final line (complete or interrupted,
// resumed cases left out of the rate).

#include "deploysim/sweep/progress.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <regex>
#include <sstream>
#include <string>

namespace deploysim::sweep {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

TEST(ProgressTest, DurationsAreSecondsMinutesOrHours) {
  EXPECT_EQ(ProgressReporter::FormatDuration(0.0), "0 s");
  EXPECT_EQ(ProgressReporter::FormatDuration(7.4), "7 s");
  EXPECT_EQ(ProgressReporter::FormatDuration(59.4), "59 s");
  EXPECT_EQ(ProgressReporter::FormatDuration(59.5), "1:00");  // rounded first
  EXPECT_EQ(ProgressReporter::FormatDuration(123.0), "2:03");
  EXPECT_EQ(ProgressReporter::FormatDuration(3599.0), "59:59");
  EXPECT_EQ(ProgressReporter::FormatDuration(3600.0), "1:00:00");
  EXPECT_EQ(ProgressReporter::FormatDuration(3723.0), "1:02:03");
  EXPECT_EQ(ProgressReporter::FormatDuration(36.0 * 3600.0 + 61.0), "36:01:01");
  EXPECT_EQ(ProgressReporter::FormatDuration(-5.0), "0 s");
  EXPECT_EQ(ProgressReporter::FormatDuration(std::numeric_limits<double>::quiet_NaN()), "?");
  EXPECT_EQ(ProgressReporter::FormatDuration(std::numeric_limits<double>::infinity()), "?");
}

// Plain lines: none before the interval has passed (the first after one interval); with
// interval 0, one per update, counting the cases and the percentage.
TEST(ProgressTest, PlainLinesComeAtTheIntervalWithTheCounts) {
  std::ostringstream quiet;
  ProgressReporter slow(quiet, false, 10, 0, 3600.0, "grid");
  slow.Update(3);
  slow.Update(4);
  EXPECT_EQ(quiet.str(), "");

  std::ostringstream out;
  ProgressReporter r(out, false, 8, 0, 0.0, "grid");
  r.Update(2);
  r.Update(6);
  const std::regex line(
      R"(grid: (\d+)/8 cases \((\d+)%\), \d+ cases/s, \d+ s elapsed, ETA (\d+ s|\d+(:\d\d)+|\?)\n)");
  std::string text = out.str();
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, line)) << text;
  EXPECT_EQ(m[1], "2");
  EXPECT_EQ(m[2], "25");
  text = m.suffix();
  ASSERT_TRUE(std::regex_search(text, m, line)) << text;
  EXPECT_EQ(m[1], "6");
  EXPECT_EQ(m[2], "75");
  EXPECT_EQ(std::string(m.suffix()), "");
  EXPECT_EQ(out.str().find('\r'), std::string::npos);
}

// On a terminal: a 30-character bar redrawn in place (carriage return, no newline), not
// more often than every 0.2 s, and cleared before the final line.
TEST(ProgressTest, TheBarIsRedrawnInPlaceAndCleared) {
  std::ostringstream out;
  ProgressReporter r(out, true, 10, 0, 3600.0);
  r.Update(5);
  const std::string first = out.str();
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(first[0], '\r');
  EXPECT_EQ(first.find('\n'), std::string::npos);
  const std::regex bar(
      R"(\rsweep \[#{15}\.{15}\]  50% 5/10  \d+ cases/s  ETA (\d+ s|\d+(:\d\d)+|\?))");
  EXPECT_TRUE(std::regex_match(first, bar)) << first;
  r.Update(6);  // within 0.2 s of the first: not drawn
  EXPECT_EQ(out.str(), first);
  r.Finish(10, true);
  const std::string all = out.str();
  const std::string cleared = "\r" + std::string(first.size() - 1, ' ') + "\r";
  ASSERT_EQ(all.substr(first.size(), cleared.size()), cleared) << all;
  const std::string last = all.substr(first.size() + cleared.size());
  EXPECT_TRUE(std::regex_match(last, std::regex(R"(sweep: 10/10 cases done \(10 computed in )"
                                                R"(\d+ s, \d+ cases/s\)\n)")))
      << last;
}

// An interrupted, resumed sweep: the final line says so, counts only the cases this run
// computed and names the resumed ones.
TEST(ProgressTest, TheFinalLineCountsOnlyTheCasesThisRunComputed) {
  std::ostringstream out;
  ProgressReporter r(out, false, 20, 7, 3600.0, "mc");
  r.Finish(12, false);
  EXPECT_TRUE(std::regex_match(out.str(),
                               std::regex(R"(mc: 12/20 cases finished, interrupted \(5 computed )"
                                          R"(in \d+ s, \d+ cases/s, 7 resumed\)\n)")))
      << out.str();
  // Nothing finished beyond the resumed ones: 0 computed, not a negative count.
  std::ostringstream none;
  ProgressReporter n(none, false, 20, 7, 3600.0, "mc");
  n.Finish(7, false);
  EXPECT_NE(none.str().find("(0 computed in "), std::string::npos) << none.str();
  // An empty sweep is complete: 100 %.
  std::ostringstream empty;
  ProgressReporter e(empty, true, 0, 0, 0.0);
  e.Update(0);
  EXPECT_NE(empty.str().find("100% 0/0"), std::string::npos) << empty.str();
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::sweep
