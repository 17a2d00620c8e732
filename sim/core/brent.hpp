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

// Three points where f is already known (the ends and the middle of a step, say), from which a search
// may start: its first step is then the parabola through them, not a golden section.
struct BrentStart {
  int n = 0;  // 3, or 0 for none
  double x[3] = {0, 0, 0}, f[3] = {0, 0, 0};
};

// Returns the best point x found, f(x) in fx; at most 'maxIter' evaluations after the first. With a
// 'start' whose best point lies in [a, b] (the others may lie outside: they only shape the parabolas),
// the search begins from its three points and needs no first evaluation.
template <class F, class Done>
double brentMinimise(F f, double a, double b, double rel, double abs, double& fx, Done done, int maxIter = 100,
                     const BrentStart& start = {}) {
  const double cgold = 0.5 * (3.0 - std::sqrt(5.0));
  double x, wv, vv, fw, fv, e = 0, d = 0;
  int best = 0;
  for (int i = 1; i < start.n; ++i)
    if (start.f[i] < start.f[best]) best = i;
  if (start.n == 3 && start.x[best] >= a && start.x[best] <= b) {
    const int i1 = (best + 1) % 3, i2 = (best + 2) % 3, wi = start.f[i1] <= start.f[i2] ? i1 : i2, vi = 3 - best - wi;
    x = start.x[best], fx = start.f[best], wv = start.x[wi], fw = start.f[wi], vv = start.x[vi], fv = start.f[vi];
    e = d = b - a;  // (the first two parabolic steps may take up to half the interval)
  } else {
    x = wv = vv = a + cgold * (b - a);
    fx = fw = fv = f(x);
  }
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
