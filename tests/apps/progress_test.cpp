// The progress text (apps/tissuebench/progress.cpp): the bar's fill, the
// percentage and the time left, and the plain line for logs.
#include "tissuebench/progress.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

TEST(Progress, BarFillsWithTheFractionAndEstimatesTheTimeLeft) {
  const std::string s = app::format_progress("drop (leg)", 2.0, 8.0, 3.0, true);
  // a quarter done: 5 of 20 cells, 25 %, 3 s elapsed -> 9 s left
  EXPECT_NE(s.find("[#####---------------]"), std::string::npos) << s;
  EXPECT_NE(s.find(" 25%"), std::string::npos) << s;
  EXPECT_NE(s.find("t 2.00/8.00 s"), std::string::npos) << s;
  EXPECT_NE(s.find("~9.0 s left"), std::string::npos) << s;
  EXPECT_EQ(s.find('\n'), std::string::npos);
}

TEST(Progress, FullAndEmptyBars) {
  EXPECT_NE(app::format_progress("x", 5.0, 5.0, 10.0, true).find("[####################] 100%"), std::string::npos);
  const std::string start = app::format_progress("x", 0.0, 5.0, 10.0, true);
  EXPECT_NE(start.find("[--------------------]   0%"), std::string::npos) << start;
  EXPECT_NE(start.find("time left unknown"), std::string::npos) << start;
}

TEST(Progress, PlainLineForLogsHasNoBarAndLongTimesInMinutes) {
  const std::string s = app::format_progress("shear (fem)", 1.0, 4.0, 100.0, false);
  EXPECT_EQ(s.find('['), std::string::npos) << s;
  EXPECT_NE(s.find("shear (fem): 25% (t 1.00 / 4.00 s)"), std::string::npos) << s;
  EXPECT_NE(s.find("1m40s elapsed"), std::string::npos) << s;  // 100 s
  EXPECT_NE(s.find("~5m00s left"), std::string::npos) << s;    // 300 s
}

}  // namespace
