#include "deploysim/math/number_format.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace deploysim::math {
namespace {

TEST(NumberFormatTest, DataReadsBackAsTheSameDouble) {
  EXPECT_EQ(FormatNumber(40.0), "40");
  EXPECT_EQ(FormatNumber(0.1), "0.1");
  EXPECT_EQ(FormatNumber(1e-10), "1e-10");
  for (const double x :
       {1.0 / 3.0, M_PI, 2.6470816509051012e-08, 1e300, -2.5e-308, std::nextafter(1.0, 2.0)}) {
    EXPECT_EQ(std::stod(FormatNumber(x)), x) << FormatNumber(x);
  }
  EXPECT_EQ(FormatNumber(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(FormatNumber(-std::numeric_limits<double>::infinity()), "-inf");
}

TEST(NumberFormatTest, EstimatesHaveTheAskedSignificantDigits) {
  EXPECT_EQ(FormatSignificant(0.000123456), "0.000123");
  EXPECT_EQ(FormatSignificant(1234567.0), "1.23e+06");
  EXPECT_EQ(FormatSignificant(40.0), "40");
  EXPECT_EQ(FormatSignificant(M_PI, 6), "3.14159");
  EXPECT_EQ(FormatSignificant(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(FormatSignificant(-std::numeric_limits<double>::infinity(), 6), "-inf");
  EXPECT_EQ(FormatSignificant(std::copysign(std::nan(""), -1.0)), "nan");  // never "-nan"
}

}  // namespace
}  // namespace deploysim::math
