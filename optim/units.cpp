// Units of the scene parameters (units.hpp): the numeric scalar keys of README "Scene files".
#include "optim/units.hpp"

#include <map>

namespace lg::optim {

std::string parameterUnit(const std::string& path) {
  static const std::map<std::string, std::string> units{
      // bodies, stops, cases
      {"mass", "kg"}, {"max_distance", "m"}, {"min_distance", "m"}, {"sink_speed", "m/s"}, {"lift_ratio", "-"},
      {"duration", "s"}, {"ratio", "-"},
      // shock absorber
      {"L0", "m"}, {"D", "m"}, {"D2", "m"}, {"p01", "Pa"}, {"Omega0", "m^3"}, {"n", "-"}, {"rho", "kg/m^3"},
      {"f1", "m^2"}, {"f2", "m^2"}, {"xi1", "-"}, {"xi2", "-"}, {"mu", "-"}, {"friction_velocity", "m/s"},
      {"p_atm", "Pa"},
      // tyre
      {"radius", "m"}, {"K", "N/m"}, {"delta_max", "m"}, {"alpha", "-"}, {"ground_height", "m"},
      // spring-damper
      {"k", "N/m"}, {"c", "N s/m"},
  };
  const auto dot = path.rfind('.');
  const auto it = units.find(dot == std::string::npos ? path : path.substr(dot + 1));
  return it == units.end() ? "?" : it->second;
}

}  // namespace lg::optim
