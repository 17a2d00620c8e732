// Which unknowns of a fit the data determine (calib/fit.hpp calls it at the optimum).
//
// Jn is the weighted Jacobian with its columns scaled to unit length. Each singular value s_k (right
// singular vector v_k) must exceed both 'threshold' times the largest and 10 times what the columns'
// own errors could give Jn v_k, sum_i |v_ik| e_i, with e_i the error of column i estimated from a
// second Jacobian (ResidualJacobian::secondJacobian: central differences with twice the steps; an exact
// Jacobian has none). Else the unknowns are not identifiable, and the message names those with a share
// of at least 0.1 in the null direction, with the direction as relative changes ("+0.5 % strut.f1 with
// +1 % strut.xi1" for an orifice area and its loss coefficient, which enter the model only as xi1 / f1^2).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

namespace lg::calib {

struct Identifiability {
  bool identifiable = true;
  double rcond = 0;       // smallest / largest singular value of Jn
  double threshold = 0;   // FitSettings::identifiability
  std::vector<double> columnError;  // per unknown: estimated error of its column of Jn (empty: none)
  double limit = 0;       // the smallest singular value accepted in the weakest direction, relative to the largest
  std::vector<std::size_t> involved;  // unknowns in the null directions
  std::string message;    // for people; empty when identifiable
};

// J: the stacked weighted Jacobian (residuals x unknowns, in the unknowns' units) at the values x; J2
// (empty: none) a second estimate of J whose difference to it estimates J's error.
Identifiability identifiability(const Eigen::MatrixXd& J, const Eigen::MatrixXd& J2, const std::vector<double>& x,
                                const std::vector<std::string>& names, const std::vector<std::string>& units, double threshold);

}  // namespace lg::calib
