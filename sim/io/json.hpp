// JSON text for every program's output files (summary.json, result.json, compliance.json): one
// escaping rule and one number format.
#pragma once

#include <string>

namespace lg {

// A JSON string literal: quotes, backslashes and control characters escaped (\n, \t, \r, \u00XX).
std::string jsonString(const std::string& s);
// A JSON number with 17 significant digits (exact round trip); null when not finite.
std::string jsonNumber(double v);
inline const char* jsonBool(bool b) { return b ? "true" : "false"; }

}  // namespace lg
