#pragma once

/// The one rule for writing numbers as text in deploysim (file attributes, CSV tables,
/// error messages): the shortest decimal that reads back as exactly the same double.

#include <string>

namespace deploysim::math {

/// Shortest decimal text that reads back as exactly x ("40", "0.1", "1e-10",
/// "60.000000000001"); "nan", "inf", "-inf" for non-finite values (std::to_chars).
std::string FormatNumber(double x);

}  // namespace deploysim::math
