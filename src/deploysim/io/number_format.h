#pragma once

/// Number formatting shared by the io writers and error messages (internal to io).

#include <string>

namespace deploysim::io::internal {

/// Shortest decimal text that reads back as exactly x ("40", "0.1", "1e-10",
/// "60.000000000001"); "nan", "inf", "-inf" for non-finite values.
std::string FormatNumber(double x);

}  // namespace deploysim::io::internal
