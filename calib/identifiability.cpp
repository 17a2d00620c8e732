// Identifiability of a fit's unknowns from its Jacobian (identifiability.hpp).
#include "calib/identifiability.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lg::calib {
namespace {

std::string number(double v, int digits = 4) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

}  // namespace

Identifiability identifiability(const Eigen::MatrixXd& J, const Eigen::MatrixXd& J2, const std::vector<double>& x,
                                const std::vector<std::string>& names, const std::vector<std::string>& units, double threshold) {
  Identifiability id;
  id.threshold = threshold;
  const Eigen::Index n = J.cols();
  Eigen::VectorXd norm(n);
  for (Eigen::Index i = 0; i < n; ++i) norm[i] = J.col(i).norm();
  // An unknown no residual depends on.
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(norm[i] > 0)) {
      id.identifiable = false;
      id.involved.push_back(static_cast<std::size_t>(i));
      id.message += (id.message.empty() ? "" : "; ") + names[static_cast<std::size_t>(i)] +
                    " changes no fitted residual: the data say nothing about it";
    }
  if (!id.identifiable) return id;
  const Eigen::MatrixXd Jn = J * norm.cwiseInverse().asDiagonal();
  if (J2.size() == J.size())  // each column's error: its difference to the second Jacobian's
    for (Eigen::Index i = 0; i < n; ++i) id.columnError.push_back((J.col(i) - J2.col(i)).norm() / norm[i]);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Jn, Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();  // decreasing
  id.rcond = sv[n - 1] / sv[0];
  // The smallest singular value each direction must have: the threshold, and 10 times what the columns'
  // errors could give Jn v alone.
  auto limitOf = [&](Eigen::Index k) {
    double e = 0;
    for (Eigen::Index i = 0; i < n && !id.columnError.empty(); ++i)
      e += std::abs(svd.matrixV()(i, k)) * id.columnError[static_cast<std::size_t>(i)];
    return std::max(threshold, 10 * e / sv[0]);
  };
  id.limit = limitOf(n - 1);
  std::vector<bool> in(static_cast<std::size_t>(n), false);
  std::string limits;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double limit = limitOf(k);
    if (sv[k] >= limit * sv[0]) continue;
    id.identifiable = false;
    // The null direction in the unknowns' own units, then as changes relative to the values (absolute
    // where a value is 0), the largest 1 %.
    const Eigen::VectorXd v = svd.matrixV().col(k);
    std::vector<double> change(static_cast<std::size_t>(n));
    double big = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double dx = v[i] / norm[i], xi = x[static_cast<std::size_t>(i)];
      change[static_cast<std::size_t>(i)] = xi != 0 ? dx / std::abs(xi) : dx;
      if (std::abs(v[i]) >= 0.1) big = std::max(big, std::abs(change[static_cast<std::size_t>(i)]));
    }
    std::string dir;
    for (Eigen::Index i = 0; i < n; ++i) {
      const std::size_t ii = static_cast<std::size_t>(i);
      if (std::abs(v[i]) < 0.1) continue;  // a small share of the direction
      in[ii] = true;
      const double c = change[ii] / big * 0.01;
      dir += std::string(dir.empty() ? "" : " with ") + (c >= 0 ? "+" : "") +
             (x[ii] != 0 ? number(100 * c, 3) + " % " : number(c, 3) + " " + units[ii] + " ") + names[ii];
    }
    id.message += std::string(id.message.empty() ? "" : "; ") + dir + " leaves every fitted residual unchanged (singular value " +
                  number(sv[k] / sv[0], 2) + " of the largest, below the limit " + number(limit, 2) + ")";
  }
  if (id.identifiable) return id;
  std::string list;
  for (Eigen::Index i = 0; i < n; ++i)
    if (in[static_cast<std::size_t>(i)]) id.involved.push_back(static_cast<std::size_t>(i));
  for (std::size_t k = 0; k < id.involved.size(); ++k)
    list += std::string(k == 0 ? "" : k + 1 == id.involved.size() ? " and " : ", ") + names[id.involved[k]];
  id.message = "not identifiable: " + list + ": " + id.message + "; the limit is the larger of the identifiability "
               "threshold " + number(threshold, 2) + " and 10 times what the Jacobian's own error could give the direction. The data determine only a combination of them (they may enter the model only together, as an "
               "orifice area and its loss coefficient do in xi1 / f1^2): fix all but one at known values, or add "
               "measurements that separate them.";
  return id;
}

}  // namespace lg::calib
