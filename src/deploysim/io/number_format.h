#pragma once

/// io's name for the project's number formatting (internal to io): the rule itself is
/// math::FormatNumber (deploysim/math/number_format.h), defined once.

#include "deploysim/math/number_format.h"

namespace deploysim::io::internal {

using math::FormatNumber;

}  // namespace deploysim::io::internal
