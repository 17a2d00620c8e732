// Local, normalised sensitivities at a baseline: elasticities E_i = d ln f / d ln x_i = (x_i / f) df/dx_i,
// here by central differences with a relative step h:
//   x_i^+- = x_i (1 +- h),   E_i = (f(x^+) - f(x^-)) / (2 h f(x)).
// Design (2d+1 runs): run 0 the baseline, run 1 + 2i the plus point of x_i, run 2 + 2i its minus point.
// E_i is NaN, with the reason in 'why', where f(x) = 0 (no logarithm), a run failed, or x_i = 0.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace lg::uq {

// The 2d+1 points (physical units), row-major.
std::vector<double> localDesign(const std::vector<double>& x0, double h);

struct Elasticities {
  double baseline = 0;             // f(x0)
  std::vector<double> E;           // per variable [-]
  std::vector<double> derivative;  // df/dx_i [output unit / variable unit]
  std::vector<std::string> why;    // empty where E_i is defined
};

// From one output's 2d+1 values in run order.
Elasticities elasticities(const std::vector<double>& x0, double h, const std::vector<double>& y);

}  // namespace lg::uq
