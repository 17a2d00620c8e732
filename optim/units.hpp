// SI units of the numeric scene parameters a study can vary ("strut.f1" -> "m^2"), for the headers of
// every output that lists design variables.
#pragma once

#include <string>

namespace lg::optim {

// The unit of a parameter path "<element>.<key>" by its key; "-" for a dimensionless one, "?" for a
// key this table does not know.
std::string parameterUnit(const std::string& path);

// "strut.f1[m^2]": a column header.
inline std::string parameterHeader(const std::string& path) { return path + "[" + parameterUnit(path) + "]"; }

}  // namespace lg::optim
