// Brent's minimisation of a function of one variable on [a, b] without derivatives (Forsythe, Malcolm &
// Moler's fmin: golden sections, and parabolic steps through the three best points where they stay
// inside and shrink), to the tolerance tol1 = rel |x| + abs / 3: rel = sqrt(eps) where only values
// decide (near a minimum they are equal to round-off within that), rel = 0 for a fixed absolute one.
// 'done(fx)' ends the search as soon as the best value found is good enough (a search for any point
// below zero). Used by the drop observer (extrema on the dense output) and the integrators (a stop
// reached only inside a step).
#pragma once

#include <cmath>

namespace lg {

// Returns the best point x found, f(x) in fx; at most 'maxIter' evaluations after the first.
template <class F, class Done>
double brentMinimise(F f, double a, double b, double rel, double abs, double& fx, Done done, int maxIter = 100) {
  const double cgold = 0.5 * (3.0 - std::sqrt(5.0));
  double x = a + cgold * (b - a), wv = x, vv = x, e = 0, d = 0;
  fx = f(x);
  double fw = fx, fv = fx;
  for (int it = 0; it < maxIter && !done(fx); ++it) {
    const double xm = 0.5 * (a + b), tol1 = rel * std::abs(x) + abs / 3, tol2 = 2 * tol1;
    if (std::abs(x - xm) <= tol2 - 0.5 * (b - a)) break;
    bool golden = true;
    if (std::abs(e) > tol1) {  // a parabola through x, w, v
      double r = (x - wv) * (fx - fv), q = (x - vv) * (fx - fw), p = (x - vv) * q - (x - wv) * r;
      q = 2 * (q - r);
      if (q > 0) p = -p;
      q = std::abs(q);
      const double eOld = e;
      e = d;
      if (std::abs(p) < std::abs(0.5 * q * eOld) && p > q * (a - x) && p < q * (b - x)) {
        d = p / q;
        const double u = x + d;
        if (u - a < tol2 || b - u < tol2) d = xm >= x ? tol1 : -tol1;
        golden = false;
      }
    }
    if (golden) {
      e = (x >= xm ? a : b) - x;
      d = cgold * e;
    }
    const double u = std::abs(d) >= tol1 ? x + d : x + (d > 0 ? tol1 : -tol1);
    const double fu = f(u);
    if (fu <= fx) {
      (u >= x ? a : b) = x;
      vv = wv, fv = fw, wv = x, fw = fx, x = u, fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || wv == x) {
        vv = wv, fv = fw, wv = u, fw = fu;
      } else if (fu <= fv || vv == x || vv == wv) {
        vv = u, fv = fu;
      }
    }
  }
  return x;
}

}  // namespace lg
