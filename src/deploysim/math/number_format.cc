#include "deploysim/math/number_format.h"

#include <charconv>

namespace deploysim::math {

std::string FormatNumber(double x) {
  char buf[32];  // the longest shortest-round-trip double, "-2.2250738585072014e-308", is 24
  const std::to_chars_result r = std::to_chars(buf, buf + sizeof(buf), x);
  return std::string(buf, r.ptr);
}

}  // namespace deploysim::math
