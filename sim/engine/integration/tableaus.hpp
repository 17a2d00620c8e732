// The coefficients of the adaptive methods: Dormand-Prince 5(4) and the Rosenbrock-W methods ROS2 and
// ROS34PW2 (in the transformed form the step uses).
#pragma once

#include <Eigen/Dense>
#include <cmath>

namespace lg {

// Dormand-Prince 5(4): nodes c, stages a (row 6 = the 5th-order weights b), error weights e = b - b_hat.
namespace dopri {
static constexpr double c[7] = {0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1, 1};
static constexpr double a[7][6] = {
    {0, 0, 0, 0, 0, 0},
    {1.0 / 5, 0, 0, 0, 0, 0},
    {3.0 / 40, 9.0 / 40, 0, 0, 0, 0},
    {44.0 / 45, -56.0 / 15, 32.0 / 9, 0, 0, 0},
    {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0, 0},
    {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0},
    {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
static constexpr double e[7] = {71.0 / 57600, 0, -71.0 / 16695, 71.0 / 1920, -17253.0 / 339200, 22.0 / 525,
                                -1.0 / 40};
}  // namespace dopri

// A Rosenbrock-W method given as (alpha, Gamma, b, b_hat) with Gamma_ii = gamma, stored in the
// transformed form used by the step (Hairer & Wanner IV.7.25): A = alpha Gamma^-1,
// C = diag(1/gamma) - Gamma^-1, m = b Gamma^-1, e = (b - b_hat) Gamma^-1.
struct RosenbrockTableau {
  int stages = 0, embeddedOrder = 0;
  double gamma = 0;
  // Whether W holds the force elements' position stiffness k as well as their damping c (see solveW).
  // ROS34PW2 gains from it (on the seed gear's limit drop, 0.06 % peak-load error in 63 steps where the
  // damping alone needs 104 for 0.1 %); ROS2 loses (its first-order embedded estimate, the linearly
  // implicit Euler step, then under-reports: at rtol 1e-3 -0.06 % in 612 steps against -0.002 % in 1003,
  // the same with the whole Jacobian by finite differences), so it keeps the damping alone.
  bool stiffnessInW = false;
  double A[4][4] = {}, C[4][4] = {}, m[4] = {}, e[4] = {};
  // The continuous extension (hasDense; else the step's dense output is a cubic Hermite): over the step,
  //   y(t_n + theta h) = y_n + sum_j (d[j][0] theta + d[j][1] theta^2 + d[j][2] theta^3) U_j,
  // d = B Gamma^-1 in the transformed form, where b_i(theta) = sum_p B[i][p] theta^(p+1) are the weights on
  // the stages k_i that satisfy the order conditions of the Rosenbrock method up to order 3 at every theta
  // (Hairer & Wanner IV.7, table 7.1, with the right-hand sides those of y(t_n + theta h)):
  //   sum_i b_i(theta)                        = theta
  //   sum_i b_i(theta) beta_i                 = theta^2/2 - gamma theta
  //   sum_i b_i(theta) alpha_i^2              = theta^3/3
  //   sum_i b_i(theta) sum_j beta_ij beta_j   = theta^3/6 - gamma theta^2 + gamma^2 theta
  // (beta_ij = alpha_ij + gamma_ij, beta_i = sum_j<i beta_ij, alpha_i = sum_j<i alpha_ij): four conditions
  // on four stages, for each power of theta a 4 x 4 system. At theta = 1 they are the method's own, so
  // b_i(1) = b_i and the extension ends at y_n+1. Unlike the Hermite cubic it never evaluates f at the
  // step's end, whose stiff components the W-matrix damps but f multiplies by the stiff eigenvalue: on a
  // stiff step (h lambda ~ 30) a velocity slightly off its slow manifold made the Hermite cubic overshoot
  // a strut's rate 2-fold inside the step.
  bool hasDense = false;
  double d[4][3] = {};

  static RosenbrockTableau make(int s, int embeddedOrder, double gamma, const double (&alpha)[4][4],
                                const double (&Gam)[4][4], const double (&b)[4], const double (&bhat)[4]) {
    RosenbrockTableau t;
    t.stages = s;
    t.embeddedOrder = embeddedOrder;
    t.gamma = gamma;
    double G[4][4] = {}, Gi[4][4] = {};  // Gamma (lower triangular, gamma on the diagonal) and its inverse
    for (int i = 0; i < s; ++i)
      for (int j = 0; j < i; ++j) G[i][j] = Gam[i][j];
    for (int i = 0; i < s; ++i) G[i][i] = gamma;
    for (int i = 0; i < s; ++i) {  // forward substitution, column by column
      Gi[i][i] = 1.0 / gamma;
      for (int r = i + 1; r < s; ++r) {
        double acc = 0;
        for (int c = i; c < r; ++c) acc += G[r][c] * Gi[c][i];
        Gi[r][i] = -acc / gamma;
      }
    }
    for (int i = 0; i < s; ++i)
      for (int j = 0; j < s; ++j) {
        double a = 0;
        for (int c = 0; c < s; ++c) a += alpha[i][c] * Gi[c][j];
        t.A[i][j] = a;
        t.C[i][j] = (i == j ? 1.0 / gamma : 0.0) - Gi[i][j];
        if (j >= i) t.A[i][j] = t.C[i][j] = 0;  // strictly lower (the diagonal of C cancels exactly)
      }
    if (s == 4) t.continuousExtension(alpha, Gam, Gi);
    for (int j = 0; j < s; ++j) {
      double mm = 0, ee = 0;
      for (int c = 0; c < s; ++c) {
        mm += b[c] * Gi[c][j];
        ee += (b[c] - bhat[c]) * Gi[c][j];
      }
      t.m[j] = mm;
      t.e[j] = ee;
    }
    return t;
  }
  // The weights d of the continuous extension of order 3 (see hasDense) of a 4-stage method, Gi = Gamma^-1.
  void continuousExtension(const double (&alpha)[4][4], const double (&Gam)[4][4], const double (&Gi)[4][4]) {
    double beta[4];  // beta_i = sum_j<i beta_ij
    for (int i = 0; i < 4; ++i) {
      beta[i] = 0;
      for (int j = 0; j < i; ++j) beta[i] += alpha[i][j] + Gam[i][j];
    }
    Eigen::Matrix4d M;  // M(condition, stage)
    for (int i = 0; i < 4; ++i) {
      double a = 0, bb = 0;
      for (int j = 0; j < i; ++j) {
        a += alpha[i][j];
        bb += (alpha[i][j] + Gam[i][j]) * beta[j];
      }
      M.col(i) << 1, beta[i], a * a, bb;
    }
    const double g = gamma;
    Eigen::Matrix<double, 4, 3> rhs;  // the conditions' right-hand sides by power: theta, theta^2, theta^3
    rhs << 1, 0, 0, -g, 0.5, 0, 0, 0, 1.0 / 3, g * g, -g, 1.0 / 6;
    const Eigen::Matrix<double, 4, 3> B = M.partialPivLu().solve(rhs);
    for (int j = 0; j < 4; ++j)
      for (int p = 0; p < 3; ++p) {
        double v = 0;
        for (int i = 0; i < 4; ++i) v += B(i, p) * Gi[i][j];
        d[j][p] = v;
      }
    hasDense = true;
  }
  // ROS2 (Verwer, Spee, Blom & Hundsdorfer 1999): order 2, L-stable, gamma = 1 + 1/sqrt(2); the
  // embedded method is first order.
  static const RosenbrockTableau& ros2() {
    static const RosenbrockTableau t = [] {
      const double g = 1.0 + 1.0 / std::sqrt(2.0);
      const double alpha[4][4] = {{0}, {1.0}};
      const double Gam[4][4] = {{0}, {-2.0 * g}};
      const double b[4] = {0.5, 0.5}, bhat[4] = {1.0, 0.0};
      return make(2, 1, g, alpha, Gam, b, bhat);
    }();
    return t;
  }
  // ROS34PW2 (Rang & Angermann 2005): a W-method of order 3 with an embedded order-2 method, 4 stages,
  // L-stable and stiffly accurate.
  static const RosenbrockTableau& ros34pw2() {
    static const RosenbrockTableau t = [] {
      const double g = 4.3586652150845900e-01;
      const double alpha[4][4] = {{0},
                                  {8.7173304301691801e-01},
                                  {8.4457060015369423e-01, -1.1299064236484185e-01},
                                  {0.0, 0.0, 1.0}};
      const double Gam[4][4] = {{0},
                                {-8.7173304301691801e-01},
                                {-9.0338057013044082e-01, 5.4180672388095326e-02},
                                {2.4212380706095346e-01, -1.2232505839045147e+00, 5.4526025533510214e-01}};
      const double b[4] = {2.4212380706095346e-01, -1.2232505839045147e+00, 1.5452602553351020e+00,
                           4.3586652150845900e-01};
      const double bhat[4] = {3.7810903145819369e-01, -9.6042292212423178e-02, 5.0000000000000000e-01,
                              2.1793326075422950e-01};
      RosenbrockTableau t = make(4, 2, g, alpha, Gam, b, bhat);
      t.stiffnessInW = true;
      return t;
    }();
    return t;
  }
};

}  // namespace lg
