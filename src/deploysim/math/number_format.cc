#include "deploysim/math/number_format.h"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace deploysim::math {

std::string FormatNumber(double x) {
  char buf[32];  // the longest shortest-round-trip double, "-2.2250738585072014e-308", is 24
  const std::to_chars_result r = std::to_chars(buf, buf + sizeof(buf), x);
  return std::string(buf, r.ptr);
}

std::string FormatSignificant(double x, int digits) {
  if (std::isnan(x)) return "nan";  // printf writes "-nan" for a NaN with its sign bit set
  char buf[40];  // "-1.2345678901234567e-308": at most 17 digits plus sign, point, exponent
  std::snprintf(buf, sizeof(buf), "%.*g", digits, x);
  return buf;
}

std::string JsonNumber(double x) { return std::isfinite(x) ? FormatNumber(x) : "null"; }

std::string JsonString(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      o += '\\';
      o += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
      o += buf;
    } else {
      o += c;
    }
  }
  return o + "\"";
}

}  // namespace deploysim::math
