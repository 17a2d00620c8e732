// A bushing: a 6-component linear spring-damper between a frame of body i and a frame of body j (the
// lumped flexibility of a strut or a fitting). Each frame has an origin rho and axes A (columns) in its
// body; in the world Q_i = R_i A_i, Q_j = R_j A_j, p_i = r_i + R_i rho_i, p_j = r_j + R_j rho_j. The
// bushing is unloaded where the two frames coincide (the scene's pose, unless point2 is given apart).
//
//   displacement (frame i)   d     = Q_i^T (p_j - p_i)                                        [m]
//   its rate                 d'    = Q_i^T (v_pj - v_i - w_i x (p_j - r_i))  (exactly dd/dt)   [m/s]
//   rotation (frame j)       theta = log(Q_i^T Q_j), the rotation vector of the relative rotation
//                                    (|theta| < pi; unloaded at theta = 0)                    [rad]
//   relative angular rate    w_rel = Q_i^T (w_j - w_i)  (frame i)                              [rad/s]
//
// with diagonal stiffness and damping per axis of frame i: K_t = diag(k_x, k_y, k_z), C_t, K_r, C_r.
//
//   stored    E = d.K_t d / 2 + theta.K_r theta / 2                          (exact for this measure)
//   force on body j, at p_j:         f = -Q_i (K_t d + C_t d')  ; on body i -f, also at p_j
//   moment on body j:        tau = -Q_j Jr^-T(theta) K_r theta - Q_i C_r w_rel ; on body i -tau
//   dissipation rate         d'.C_t d' + w_rel.C_r w_rel
//
// The elastic parts are minus the gradient of E: a variation of body i's pose moves frame i with it,
// hence the force on body i acts at p_j, not p_i; and a rotation dphi (world) of body j or i changes
// theta by Jr^-1(theta) Q_j^T (dphi_j - dphi_i), Jr the right Jacobian of SO(3):
//   Jr^-1(theta) = I + [theta]x / 2 + b(|theta|) [theta]x^2,  b = 1/t^2 - (1 + cos t)/(2 t sin t)
// (b = 1/12 + t^2/720 + t^4/30240 below t = 1e-2). About a single axis Jr^-1 theta = theta: the moment is
// exactly -k_r theta for any angle. The damping is exact too: each of its six components is a rank-1
// DampingTerm (rate d'_k along the k-th axis of frame i at p_j, or w_rel,k), so the linearly implicit
// integrators take the bushing's whole velocity stiffness; each term also carries its axis's stiffness
// (k_t,k exact; k_r,k that of theta about axis k as w_rel,k were its rate, exact at small angles).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "sim/core/body.hpp"

namespace lg {

template <class S> struct Bushing {
  static constexpr int kDissipation = 1;
  static constexpr int kDamping = 6;
  static constexpr int kEvents = 0;
  int bi = kGround, bj = kGround;
  Vec3<S> rho_i, rho_j;  // [m] frame origins in the bodies
  Mat3<S> A_i, A_j;      // [-] frame axes in the bodies (columns x, y, z)
  Vec3<S> kt = Vec3<S>::Zero();  // [N/m] translational stiffness along x, y, z of frame i
  Vec3<S> ct = Vec3<S>::Zero();  // [N s/m] translational damping
  Vec3<S> kr = Vec3<S>::Zero();  // [N m/rad] rotational stiffness about x, y, z of frame i
  Vec3<S> cr = Vec3<S>::Zero();  // [N m s/rad] rotational damping

  struct Eval {
    Mat3<S> Qi, Qj;
    Vec3<S> armI, armJ;  // [m] lever arms of p_j from the centres of mass of bodies i and j
    Vec3<S> d, ddot, theta, wrel;
    Mat3<S> JrInv;
  };

  // The rotation vector of a rotation matrix through its unit quaternion (Shepperd's choice of the
  // largest component, then w >= 0); near theta = 0 a series, so that a Jet differentiates it there.
  static Vec3<S> logMap(const Mat3<S>& R) {
    using std::atan2;
    using std::sqrt;
    const S t = R(0, 0) + R(1, 1) + R(2, 2);
    S w;
    Vec3<S> v;
    const double tv = value(t), d0 = value(R(0, 0)), d1 = value(R(1, 1)), d2 = value(R(2, 2));
    if (tv >= d0 && tv >= d1 && tv >= d2) {
      const S s = sqrt(S(1) + t) * S(2);  // 4 w
      w = s / S(4);
      v << (R(2, 1) - R(1, 2)) / s, (R(0, 2) - R(2, 0)) / s, (R(1, 0) - R(0, 1)) / s;
    } else if (d0 >= d1 && d0 >= d2) {
      const S s = sqrt(S(1) + R(0, 0) - R(1, 1) - R(2, 2)) * S(2);
      w = (R(2, 1) - R(1, 2)) / s;
      v << s / S(4), (R(0, 1) + R(1, 0)) / s, (R(0, 2) + R(2, 0)) / s;
    } else if (d1 >= d2) {
      const S s = sqrt(S(1) + R(1, 1) - R(0, 0) - R(2, 2)) * S(2);
      w = (R(0, 2) - R(2, 0)) / s;
      v << (R(0, 1) + R(1, 0)) / s, s / S(4), (R(1, 2) + R(2, 1)) / s;
    } else {
      const S s = sqrt(S(1) + R(2, 2) - R(0, 0) - R(1, 1)) * S(2);
      w = (R(1, 0) - R(0, 1)) / s;
      v << (R(0, 2) + R(2, 0)) / s, (R(1, 2) + R(2, 1)) / s, s / S(4);
    }
    if (value(w) < 0) {
      w = -w;
      v = -v;
    }
    const S s2 = v.squaredNorm();
    S f;  // theta = 2 atan2(|v|, w) / |v| * v
    if (value(s2) < 1e-6) {
      const S x = s2 / (w * w);
      f = (S(1) - x / S(3) + x * x / S(5)) / w;  // atan(u)/u, u = |v|/w, to O(u^6) ~ 1e-18
    } else {
      const S s = sqrt(s2);
      f = atan2(s, w) / s;
    }
    return S(2) * f * v;
  }
  // Jr^-1(theta) (see the header comment).
  static Mat3<S> rightJacobianInverse(const Vec3<S>& theta) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const S t2 = theta.squaredNorm();
    S b;
    if (value(t2) < 1e-4) {
      b = S(1) / S(12) + t2 / S(720) + t2 * t2 / S(30240);
    } else {
      const S t = sqrt(t2);
      b = S(1) / t2 - (S(1) + cos(t)) / (S(2) * t * sin(t));
    }
    const Mat3<S> X = skew(theta);
    return Mat3<S>::Identity() + X / S(2) + b * (X * X);
  }

  Eval eval(const Kins<S>& K) const {
    Eval e;
    const BodyKin<S>& Bi = K[bi];
    const BodyKin<S>& Bj = K[bj];
    e.Qi = Bi.R * A_i;
    e.Qj = Bj.R * A_j;
    const Vec3<S> aj = Bj.R * rho_j;
    const Vec3<S> pj = Bj.r + aj;
    const Vec3<S> pi = Bi.r + Bi.R * rho_i;
    e.armJ = aj;
    e.armI = pj - Bi.r;
    e.d = e.Qi.transpose() * (pj - pi);
    e.ddot = e.Qi.transpose() * (Bj.pointVelocity(aj) - Bi.pointVelocity(e.armI));
    e.theta = logMap(Mat3<S>(e.Qi.transpose() * e.Qj));
    e.wrel = e.Qi.transpose() * (Bj.w - Bi.w);
    e.JrInv = rightJacobianInverse(e.theta);
    return e;
  }
  // Force and moment on body j (world): f, tau as in the header comment.
  void wrench(const Eval& e, Vec3<S>& f, Vec3<S>& tau) const {
    f = -(e.Qi * (kt.cwiseProduct(e.d) + ct.cwiseProduct(e.ddot)));
    tau = -(e.Qj * (e.JrInv.transpose() * kr.cwiseProduct(e.theta))) - e.Qi * cr.cwiseProduct(e.wrel);
  }
  void apply(const Kins<S>& K, const Wrenches<S>& W, S* dissipation) const {
    const Eval e = eval(K);
    Vec3<S> f, tau;
    wrench(e, f, tau);
    W.addAt(bj, e.armJ, f);
    W.addAt(bi, e.armI, Vec3<S>(-f));
    if (bj >= 0) W.w[bj].template tail<3>() += tau;
    if (bi >= 0) W.w[bi].template tail<3>() -= tau;
    dissipation[0] = e.ddot.dot(ct.cwiseProduct(e.ddot)) + e.wrel.dot(cr.cwiseProduct(e.wrel));
  }
  S stored(const Kins<S>& K) const {
    const Eval e = eval(K);
    return (e.d.dot(kt.cwiseProduct(e.d)) + e.theta.dot(kr.cwiseProduct(e.theta))) / S(2);
  }
  void events(const Kins<S>&, S*) const {}
  // Six rank-1 terms: d'_k = G V along the k-th axis e_k of frame i at p_j (DampingTerm::setAxial,
  // lever arms p_j - r_i and p_j - r_j), w_rel,k = e_k.(w_j - w_i); c = C_t,k and C_r,k, k = K_t,k and K_r,k.
  void damping(const Kins<S>& K, DampingTerm<S>* d) const {
    const Eval e = eval(K);
    for (int k = 0; k < 3; ++k) {
      const Vec3<S> ek = e.Qi.col(k);
      d[k].setAxial(bi, bj, ek, e.armI, e.armJ, ct[k], kt[k]);
      DampingTerm<S>& r = d[3 + k];
      r.bi = bi;
      r.bj = bj;
      r.Gi << Vec3<S>::Zero(), -ek;
      r.Gj << Vec3<S>::Zero(), ek;
      r.c = cr[k];
      r.k = kr[k];
    }
  }
  // Force and moment on body j in frame i, the displacement and the rotation vector.
  static std::vector<std::string> outputNames() {
    return {"F_x", "F_y", "F_z", "M_x", "M_y", "M_z", "d_x", "d_y", "d_z", "theta_x", "theta_y", "theta_z"};
  }
  static const char* outputUnit(const std::string& n) {
    return n[0] == 'F' ? "N" : n[0] == 'M' ? "N m" : n[0] == 'd' ? "m" : "rad";
  }
  void outputs(const Kins<S>& K, S* out) const {
    const Eval e = eval(K);
    Vec3<S> f, tau;
    wrench(e, f, tau);
    const Vec3<S> fl = e.Qi.transpose() * f, ml = e.Qi.transpose() * tau;
    for (int k = 0; k < 3; ++k) {
      out[k] = fl[k];
      out[3 + k] = ml[k];
      out[6 + k] = e.d[k];
      out[9 + k] = e.theta[k];
    }
  }
  // Design parameters: k_x .. k_z, c_x .. c_z, k_rx .. k_rz, c_rx .. c_rz (the scene's keys).
  S* parameter(const std::string& key) {
    static const char* axes[3] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) {
      if (key == std::string("k_") + axes[k]) return &kt[k];
      if (key == std::string("c_") + axes[k]) return &ct[k];
      if (key == std::string("k_r") + axes[k]) return &kr[k];
      if (key == std::string("c_r") + axes[k]) return &cr[k];
    }
    return nullptr;
  }
  template <class T> Bushing<T> cast() const {
    return {bi, bj, castVec<T>(rho_i), castVec<T>(rho_j), A_i.template cast<T>(), A_j.template cast<T>(),
            castVec<T>(kt), castVec<T>(ct), castVec<T>(kr), castVec<T>(cr)};
  }
};

}  // namespace lg
