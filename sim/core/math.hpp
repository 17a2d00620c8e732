// Small vector algebra shared by the engine, and the one place where the code branches on a value.
//
// Everything is templated on the scalar S so that the same code runs with double and with
// ceres::Jet<double, N> (derivatives with respect to design parameters). A branch on a value
// (a sign, a max, a contact that is or is not touching) makes a derivative one-sided, so such
// branches live here, behind named helpers, and nowhere else in the physics.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <type_traits>

namespace lg {

template <class S> using Vec3 = Eigen::Matrix<S, 3, 1>;
template <class S> using Mat3 = Eigen::Matrix<S, 3, 3>;
template <class S> using Vec4 = Eigen::Matrix<S, 4, 1>;  // quaternion (w, a, b, c)
template <class S> using Vec6 = Eigen::Matrix<S, 6, 1>;  // (v, omega) of one body
template <class S> using VecX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
template <class S> using MatX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;

// ---- scalar traits: the value part of a scalar ------------------------------------------------
template <class S> struct ScalarTraits {
  static double value(const S& x) { return static_cast<double>(x); }
  static bool exactZero(const S& x) { return x == S(0); }
};
template <class S> inline double value(const S& x) { return ScalarTraits<S>::value(x); }
// Zero in value and in every derivative part: a term that changes nothing, not even a derivative.
template <class S> inline bool exactZero(const S& x) { return ScalarTraits<S>::exactZero(x); }

// Lift a double constant into S.
template <class S> inline S constant(double x) { return S(x); }

using std::abs;
using std::sqrt;
using std::pow;
using std::tanh;

// ---- the branches on a value ------------------------------------------------------------------
// max(x, 0): the tyre never pulls. Kink at 0 (one-sided derivative there).
template <class S> inline S positivePart(const S& x) { return value(x) > 0.0 ? x : S(0.0); }
// x |x|: the orifice law. C1 (derivative 2|x|), so no event is needed.
template <class S> inline S signedSquare(const S& x) { return value(x) >= 0.0 ? x * x : -(x * x); }
// |x|: the orifice's damping 2 |x| (the derivative of x |x|). Kink at 0, where the right-hand
// derivative is taken (sqrt(x^2) would give a NaN derivative there); for doubles equal to sqrt(x^2).
template <class S> inline S magnitude(const S& x) { return value(x) >= 0.0 ? x : -x; }
// sgn(x) regularised over the velocity scale eps > 0: x / sqrt(x^2 + eps^2). C-infinity.
template <class S> inline S smoothSign(const S& x, double eps) {
  using std::sqrt;
  return x / sqrt(x * x + S(eps * eps));
}
// Plain comparisons made on values (never on derivatives).
template <class S> inline bool isPositive(const S& x) { return value(x) > 0.0; }
template <class S> inline bool isFinite(const S& x) { return std::isfinite(value(x)); }

// ---- rotations ---------------------------------------------------------------------------------
// R(q) for q = (w, a, b, c) = (cos(alpha/2), sin(alpha/2) u), as in method.md.
template <class S> inline Mat3<S> rotation(const Vec4<S>& q) {
  const S w = q[0], a = q[1], b = q[2], c = q[3];
  Mat3<S> R;
  R << S(1) - S(2) * (b * b + c * c), S(2) * (a * b - w * c), S(2) * (a * c + w * b),
      S(2) * (a * b + w * c), S(1) - S(2) * (a * a + c * c), S(2) * (b * c - w * a),
      S(2) * (a * c - w * b), S(2) * (b * c + w * a), S(1) - S(2) * (a * a + b * b);
  return R;
}

// [a]x with [a]x b = a x b.
template <class S> inline Mat3<S> skew(const Vec3<S>& a) {
  Mat3<S> K;
  K << S(0), -a[2], a[1], a[2], S(0), -a[0], -a[1], a[0], S(0);
  return K;
}

// dq/dt for a world-frame angular velocity omega: 0.5 (0, omega) (x) q.
template <class S> inline Vec4<S> quaternionRate(const Vec4<S>& q, const Vec3<S>& omega) {
  Vec4<S> d;
  d[0] = S(-0.5) * (omega[0] * q[1] + omega[1] * q[2] + omega[2] * q[3]);
  d[1] = S(0.5) * (omega[0] * q[0] + omega[1] * q[3] - omega[2] * q[2]);
  d[2] = S(0.5) * (omega[1] * q[0] + omega[2] * q[1] - omega[0] * q[3]);
  d[3] = S(0.5) * (omega[2] * q[0] + omega[0] * q[2] - omega[1] * q[1]);
  return d;
}

// q after a rotation by the world-frame vector theta (exact exponential map, used by projection).
template <class S> inline Vec4<S> rotateQuaternion(const Vec4<S>& q, const Vec3<S>& theta) {
  using std::cos;
  using std::sin;
  const double angle = std::sqrt(value(theta.squaredNorm()));
  Vec4<S> dq;
  if (angle < 1e-8) {  // second-order series: exact to round-off there
    dq << S(1) - theta.squaredNorm() / S(8), S(0.5) * theta[0], S(0.5) * theta[1], S(0.5) * theta[2];
  } else {
    const S a = theta.norm();
    const S s = sin(a / S(2)) / a;
    dq << cos(a / S(2)), s * theta[0], s * theta[1], s * theta[2];
  }
  // dq (x) q
  Vec4<S> r;
  r[0] = dq[0] * q[0] - dq[1] * q[1] - dq[2] * q[2] - dq[3] * q[3];
  r[1] = dq[0] * q[1] + dq[1] * q[0] + dq[2] * q[3] - dq[3] * q[2];
  r[2] = dq[0] * q[2] - dq[1] * q[3] + dq[2] * q[0] + dq[3] * q[1];
  r[3] = dq[0] * q[3] + dq[1] * q[2] - dq[2] * q[1] + dq[3] * q[0];
  return r;
}

// A unit quaternion whose frame has local x along xAxis and local z along zAxis (orthonormalised).
inline Vec4<double> quaternionFromAxes(const Vec3<double>& xAxis, const Vec3<double>& zAxis) {
  Vec3<double> ex = xAxis.normalized();
  Vec3<double> ez = (zAxis - zAxis.dot(ex) * ex).normalized();
  Vec3<double> ey = ez.cross(ex);
  Mat3<double> R;
  R.col(0) = ex;
  R.col(1) = ey;
  R.col(2) = ez;
  // Shepperd's method.
  Vec4<double> q;
  const double tr = R.trace();
  if (tr > 0) {
    double s = std::sqrt(tr + 1.0) * 2;
    q << 0.25 * s, (R(2, 1) - R(1, 2)) / s, (R(0, 2) - R(2, 0)) / s, (R(1, 0) - R(0, 1)) / s;
  } else if (R(0, 0) > R(1, 1) && R(0, 0) > R(2, 2)) {
    double s = std::sqrt(1.0 + R(0, 0) - R(1, 1) - R(2, 2)) * 2;
    q << (R(2, 1) - R(1, 2)) / s, 0.25 * s, (R(0, 1) + R(1, 0)) / s, (R(0, 2) + R(2, 0)) / s;
  } else if (R(1, 1) > R(2, 2)) {
    double s = std::sqrt(1.0 + R(1, 1) - R(0, 0) - R(2, 2)) * 2;
    q << (R(0, 2) - R(2, 0)) / s, (R(0, 1) + R(1, 0)) / s, 0.25 * s, (R(1, 2) + R(2, 1)) / s;
  } else {
    double s = std::sqrt(1.0 + R(2, 2) - R(0, 0) - R(1, 1)) * 2;
    q << (R(1, 0) - R(0, 1)) / s, (R(0, 2) + R(2, 0)) / s, (R(1, 2) + R(2, 1)) / s, 0.25 * s;
  }
  if (q[0] < 0) q = -q;
  return q.normalized();
}

// Two unit vectors completing n to a right-handed orthonormal basis (t1, t2, n).
inline void orthonormalBasis(const Vec3<double>& n, Vec3<double>& t1, Vec3<double>& t2) {
  Vec3<double> u = n.normalized();
  Vec3<double> a = std::abs(u[0]) < 0.9 ? Vec3<double>(1, 0, 0) : Vec3<double>(0, 1, 0);
  t1 = (a - a.dot(u) * u).normalized();
  t2 = u.cross(t1);
}

template <class T, class S> inline Vec3<T> castVec(const Vec3<S>& v) {
  return Vec3<T>(T(v[0]), T(v[1]), T(v[2]));
}

}  // namespace lg
