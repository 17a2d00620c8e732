// Number and field formats: exact round trip for data (CSV, gnuplot data), a few significant digits for
// people (markdown, messages). Vocabulary of every layer: the drop layer's messages, the outputs of the
// studies, the sensitivity reports and the calibration.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace lg {

// A CSV number with 17 significant digits (exact round trip); "nan" / "inf" where not finite.
inline std::string exactNumber(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// For people: 'digits' significant digits, "-" where not finite.
inline std::string shortNumber(double v, int digits = 6) {
  if (!std::isfinite(v)) return "-";
  char b[40];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

// A gnuplot data number: "?" (gnuplot's missing value) where not finite.
inline std::string plotNumber(double v) { return std::isfinite(v) ? exactNumber(v) : std::string("?"); }

// A CSV field in double quotes (quotes doubled, line breaks as spaces).
inline std::string csvField(const std::string& s) {
  std::string q = "\"";
  for (char ch : s) {
    if (ch == '"') q += "\"\"";
    else if (ch == '\n' || ch == '\r') q += ' ';
    else q += ch;
  }
  return q + "\"";
}

}  // namespace lg
