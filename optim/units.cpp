// Units of the scene parameters (units.hpp): the catalogue of sim/parameters.hpp.
#include "optim/units.hpp"

#include "sim/parameters.hpp"

namespace lg::optim {

std::string parameterUnit(const std::string& path) {
  const auto dot = path.rfind('.');
  return unitOfKey(dot == std::string::npos ? path : path.substr(dot + 1));
}

}  // namespace lg::optim
