// Self-check of the reduced (Lagrange second-kind) reference models.
// Build: g++ -std=c++20 -O2 -I/usr/include/eigen3 reduced_selfcheck.cpp -o reduced_selfcheck
// Exit status 0 when every check passes.
#include "reduced_seed_gear.hpp"
#include "reduced_telescopic.hpp"

#include <cstdio>
#include <random>
#include <string>

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
  if (!ok) {
    ++failures;
    std::printf("FAIL: %s\n", what.c_str());
  }
}

double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

// Finite-difference checks of the seed-gear kinematics, mass matrix, velocity-product terms
// (against the Christoffel symbols of FD derivatives of M), and gravity/lift forces (against -dV/dq).
void checkSeedKinematics() {
  using namespace ref;
  const SeedGearParams p;
  const SeedGearModel m(p, 3.0, 0.7);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uy(1.2, 1.6), uth(-0.6, 0.1), uv(-4.0, 4.0), uw(-20.0, 20.0);
  double eGeo = 0, eHv = 0, eQ = 0, eGrad = 0, eSqq = 0;
  const double hq = 1e-5;
  for (int trial = 0; trial < 20; ++trial) {
    const Vec2 q(uy(rng), uth(rng)), qd(uv(rng), uw(rng));
    // geometry derivatives
    const auto G = m.geo(q(0), q(1)), Gp = m.geo(q(0), q(1) + hq), Gm = m.geo(q(0), q(1) - hq);
    for (int i = 0; i < 5; ++i) {
      eGeo = std::max(eGeo, ((Gp.r[i] - Gm.r[i]) / (2 * hq) - G.r1[i]).norm());
      eGeo = std::max(eGeo, ((Gp.r1[i] - Gm.r1[i]) / (2 * hq) - G.r2[i]).norm());
    }
    eGeo = std::max(eGeo, std::abs((Gp.phi - Gm.phi) / (2 * hq) - G.phi1));
    eGeo = std::max(eGeo, std::abs((Gp.phi1 - Gm.phi1) / (2 * hq) - G.phi2));
    eGeo = std::max(eGeo, std::abs((Gp.l1 - Gm.l1) / (2 * hq) - G.l2));
    // Christoffel terms from FD of M: hv_i = sum_jk (dM_ij/dq_k - 1/2 dM_jk/dq_i) qd_j qd_k
    const Kinematics K = m.kin(q, qd);
    Mat2 dM[2];
    Vec2 dV, ds, dd;
    for (int k = 0; k < 2; ++k) {
      Vec2 e = Vec2::Zero();
      e(k) = hq;
      const Kinematics Kp = m.kin(q + e, qd), Km = m.kin(q - e, qd);
      dM[k] = (Kp.M - Km.M) / (2 * hq);
      dV(k) = (Kp.V - Km.V) / (2 * hq);
      ds(k) = (Kp.s - Km.s) / (2 * hq);
      dd(k) = (Kp.delta - Km.delta) / (2 * hq);
    }
    Vec2 hfd = Vec2::Zero();
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k) hfd(i) += (dM[k](i, j) - 0.5 * dM[i](j, k)) * qd(j) * qd(k);
    const double hsc = std::max(1.0, K.hv.norm());
    eHv = std::max(eHv, (hfd - K.hv).norm() / hsc);
    eQ = std::max(eQ, (K.Qg + dV).norm() / K.Qg.norm());
    eGrad = std::max(eGrad, std::max((ds - K.gs).norm(), (dd - K.gd).norm()));
    // qd^T Hess(s) qd by FD along the velocity direction
    const double sp = m.kin(q + hq * qd, qd).s, s0 = K.s, sm = m.kin(q - hq * qd, qd).s;
    eSqq = std::max(eSqq, std::abs((sp - 2 * s0 + sm) / (hq * hq) - K.sqq) / std::max(1.0, std::abs(K.sqq)));
  }
  std::printf("seed-gear kinematics FD check (20 random states):\n");
  std::printf("  geometry derivatives     max abs err %.2e\n", eGeo);
  std::printf("  Coriolis vs Christoffel  max rel err %.2e\n", eHv);
  std::printf("  Q_gravity+lift vs -dV/dq max rel err %.2e\n", eQ);
  std::printf("  grad s, grad delta       max abs err %.2e\n", eGrad);
  std::printf("  qd^T Hess(s) qd          max rel err %.2e\n", eSqq);
  check(eGeo < 1e-7, "geometry derivatives");
  check(eHv < 1e-6, "Coriolis terms vs Christoffel symbols");
  check(eQ < 1e-8, "gravity/lift generalized force");
  check(eGrad < 1e-8, "stroke/deflection gradients");
  check(eSqq < 1e-3, "stroke Hessian term");
  // M at t = 0 must equal the total mass in the y5-y5 entry
  const auto K0 = m.kin(m.q0(), m.qd0());
  check(rel(K0.M(0, 0), p.totalMass()) < 1e-14, "M_11 = total mass");
}

struct Case {
  const char* name;
  double V, L;
};

void printHeader() {
  std::printf("%-10s %5s %4s %12s %9s %10s %10s %10s %8s %10s %6s %4s\n", "case", "Vy0", "L", "peak Py[N]",
              "tPeak[s]", "sMax[m]", "hMax[m]", "dMax[m]", "n_y", "dE/E0", "steps", "ev");
}

void printRow(const Case& c, const ref::ReducedResult& r, double weight) {
  std::printf("%-10s %5.2f %4.1f %12.3f %9.6f %10.7f %10.7f %10.7f %8.4f %10.2e %6d %4d\n", c.name, c.V, c.L,
              r.peakLoad, r.tPeak, r.strokeMax, r.hMax, r.deltaMax, r.peakLoad / weight,
              r.energyError / r.energyInitial, r.acceptedSteps, r.events);
}

template <class Sim>
void runCases(const char* title, const Case* cases, int nc, double weight, Sim&& sim) {
  std::printf("\n%s (0.8 s, rtol 1e-10; halving rtol must move the peaks < 1e-7 relative)\n", title);
  printHeader();
  for (int i = 0; i < nc; ++i) {
    const auto r = sim(cases[i].V, cases[i].L, 1e-10);
    printRow(cases[i], r, weight);
    check(r.energyError / r.energyInitial < 1e-6, std::string(cases[i].name) + ": energy closure < 1e-6");
    const auto r2 = sim(cases[i].V, cases[i].L, 0.5e-10);
    const double d = std::max({rel(r2.peakLoad, r.peakLoad), rel(r2.strokeMax, r.strokeMax),
                               rel(r2.hMax, r.hMax), rel(r2.deltaMax, r.deltaMax)});
    const double dt = std::abs(r2.tPeak - r.tPeak);
    std::printf("%-10s   rtol/2: max rel change of peaks %.2e, |dtPeak| %.2e s, E_diss %.3f J (impacts %.3f J)\n",
                "", d, dt, r.energyDissipated, r.energyImpacts);
    check(d < 1e-7, std::string(cases[i].name) + ": peaks converged in rtol");
    for (const auto& e : r.eventLog) std::printf("%-10s   event t = %.9f s: %s\n", "", e.t, e.what);
  }
}

}  // namespace

int main() {
  checkSeedKinematics();

  const ref::SeedGearParams sp;
  const Case seed[] = {{"light", 2.0, 1.0}, {"medium", 2.6, 1.0}, {"limit", 3.05, 1.0},
                       {"reserve", 3.66, 1.0}, {"free-drop", 2.5, 0.0}};
  runCases("seed trailing-link gear", seed, 5, sp.totalMass() * sp.g,
           [&](double V, double L, double rtol) { return ref::simulateSeedGear(sp, V, L, 0.8, rtol); });

  const ref::TelescopicParams tp;
  const Case tele[] = {{"tele-2.5", 2.5, 1.0}, {"tele-3.0", 3.0, 0.8}};
  runCases("telescopic gear", tele, 2, tp.totalMass() * tp.g,
           [&](double V, double L, double rtol) { return ref::simulateTelescopic(tp, V, L, 0.8, rtol); });

  // Friction regularisation: results must converge as the velocity scale shrinks.
  std::printf("\nfriction regularisation, seed gear limit case (3.05 m/s, L = 1):\n");
  std::printf("%12s %12s %10s %10s %10s %6s\n", "eps[m/s]", "peak Py[N]", "sMax[m]", "hMax[m]", "dE/E0", "steps");
  for (double eps : {1e-2, 1e-3, 1e-4, 1e-5}) {
    ref::SeedGearParams q = sp;
    q.frictionVelocity = eps;
    const auto r = ref::simulateSeedGear(q, 3.05, 1.0, 0.8);
    std::printf("%12.0e %12.3f %10.7f %10.7f %10.2e %6d\n", eps, r.peakLoad, r.strokeMax, r.hMax,
                r.energyError / r.energyInitial, r.acceptedSteps);
  }

  std::printf("\n%s (%d failure%s)\n", failures ? "SELF-CHECK FAILED" : "SELF-CHECK PASSED", failures,
              failures == 1 ? "" : "s");
  return failures ? 1 : 0;
}
