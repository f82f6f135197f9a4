#include "deploysim/io/number_format.h"

#include <charconv>

namespace deploysim::io::internal {

std::string FormatNumber(double x) {
  char buf[32];
  const std::to_chars_result r = std::to_chars(buf, buf + sizeof(buf), x);
  return std::string(buf, r.ptr);
}

}  // namespace deploysim::io::internal
