#pragma once

/// The two rules for writing numbers as text in deploysim: data (file attributes, CSV
/// tables, JSON, values quoted in error messages) as the shortest decimal that reads back
/// as exactly the same double; estimates and table cells meant for a reader (crosscheck
/// verdicts, cost estimates, the analyze table) to a given number of significant digits.

#include <string>

namespace deploysim::math {

/// Shortest decimal text that reads back as exactly x ("40", "0.1", "1e-10",
/// "60.000000000001"); "nan", "inf", "-inf" for non-finite values (std::to_chars).
std::string FormatNumber(double x);

/// x to `digits` significant digits, printf's %g ("0.000123", "1.23e+06", "40");
/// "nan", "inf", "-inf" for non-finite values.
std::string FormatSignificant(double x, int digits = 3);

/// A JSON number: FormatNumber, or null for NaN and infinities (JSON has neither).
std::string JsonNumber(double x);

/// A JSON string literal: quotes, backslashes and control characters escaped.
std::string JsonString(const std::string& s);

}  // namespace deploysim::math
