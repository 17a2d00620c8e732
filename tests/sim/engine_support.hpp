// Helpers for the engine tests: inline scenes, a recording observer with dense-output crossing
// location, and small closed forms.
//
// Include order: the sim headers pull in glog (through ceres), whose CHECK macro replaces Catch's if it
// comes later; Catch must be included after them (this header does so), or a failed CHECK aborts the
// whole test run instead of being reported.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "sim/engine/integrators.hpp"
#include "sim/io/scene.hpp"

#include <catch2/catch.hpp>

namespace lgtest {

// Prints a measured figure when LG_TEST_VERBOSE is set (the figures quoted in the test comments).
template <class... A> void report(const char* fmt, A... a) {
  if (std::getenv("LG_TEST_VERBOSE")) {
    std::printf(fmt, a...);
    std::printf("\n");
  }
}

inline lg::Scene inlineScene(const std::string& toml) { return lg::parseScene(toml, "inline.toml"); }

// The double pendulum on revolute hinges about z (engine and multiplier-solver tests). Link 1: hinge
// at the origin, CoM c1 = 0.4 below it, second hinge l1 = 0.8 below it; link 2: CoM c2 = 0.3 below the
// second hinge. Hanging at rest in the scene.
struct DP {
  double m1 = 1.5, m2 = 1.0, c1 = 0.4, l1 = 0.8, c2 = 0.3, I1 = 0.09, I2 = 0.05;
};
inline constexpr const char* kDoublePendulum = R"(
[solver]
integrator = "dopri5"
rtol = 1e-10
atol = 1e-12

[[body]]
name = "link1"
mass = 1.5
inertia = [0.01, 0.08, 0.09]
position = [0.0, -0.4, 0.0]

[[body]]
name = "link2"
mass = 1.0
inertia = [0.005, 0.04, 0.05]
position = [0.0, -1.1, 0.0]

[[joint]]
name = "h1"
type = "revolute"
body1 = "link1"
body2 = "ground"
point = [0.0, 0.0, 0.0]
axis = [0.0, 0.0, 1.0]

[[joint]]
name = "h2"
type = "revolute"
body1 = "link2"
body2 = "link1"
point = [0.0, -0.8, 0.0]
axis = [0.0, 0.0, 1.0]

[[force]]
type = "gravity"
g = [0.0, -9.80665, 0.0]
)";

// Unit quaternion of a rotation by angle about a unit axis.
inline lg::Vec4<double> axisAngle(const lg::Vec3<double>& axis, double angle) {
  const lg::Vec3<double> u = axis.normalized();
  return lg::Vec4<double>(std::cos(angle / 2), std::sin(angle / 2) * u[0], std::sin(angle / 2) * u[1],
                          std::sin(angle / 2) * u[2]);
}

// Sets the pose and velocity of body b in a state.
inline void setBody(const lg::Model<double>& m, lg::State<double>& s, int b, const lg::Vec3<double>& r,
                    const lg::Vec4<double>& q, const lg::Vec3<double>& v, const lg::Vec3<double>& w) {
  const int N = m.nBodies();
  s.y.segment<3>(7 * b) = r;
  s.y.segment<4>(7 * b + 3) = q;
  s.y.segment<3>(7 * N + 6 * b) = v;
  s.y.segment<3>(7 * N + 6 * b + 3) = w;
}

// Largest |C| over the enforced rows at state s (kinematics and rows recomputed).
inline double positionViolation(const lg::Model<double>& m, const lg::State<double>& s) {
  lg::Workspace<double> w(m);
  lg::kinematics(m, s.y, w);
  lg::constraintRows(m, w);
  double pos, vel;
  lg::violation(m, s.active, w, pos, vel);
  return pos;
}

// x(t) of m x'' + c x' + k x = f (underdamped), x(0) = x0, x'(0) = v0: the closed form.
inline double oscillator(double m, double k, double c, double f, double x0, double v0, double t) {
  const double xeq = f / k, wn = std::sqrt(k / m), z = c / (2 * std::sqrt(k * m)), wd = wn * std::sqrt(1 - z * z);
  const double a = x0 - xeq, b = (v0 + z * wn * a) / wd;
  return xeq + std::exp(-z * wn * t) * (a * std::cos(wd * t) + b * std::sin(wd * t));
}

inline lg::EnergyReport<double> energyOf(const lg::Model<double>& m, const lg::State<double>& s) {
  lg::Workspace<double> w(m);
  lg::kinematics(m, s.y, w);
  return lg::energy(m, s, w);
}

// Records every accepted step (t, y, lambda, impact loss) and locates the upward zero crossings of
// a scalar channel f(y) on the integrator's dense output (bisection to 1e-13 s).
struct Recorder {
  struct Sample {
    double t;
    lg::VecX<double> y, lambda;
    std::vector<char> active;
    double impactLoss;
  };
  std::vector<Sample> samples;
  std::function<double(const lg::VecX<double>&)> channel;  // optional
  std::vector<double> upCrossings;
  double prevT = 0, prevF = 0;
  lg::VecX<double> tmp;

  void take(const lg::State<double>& s) { samples.push_back({s.t, s.y, s.lambda, s.active, s.impactLoss}); }
  void onStart(const lg::Model<double>& m, const lg::State<double>& s, lg::Workspace<double>&) {
    take(s);
    tmp = lg::VecX<double>::Zero(m.ny());
    if (channel) {
      prevT = s.t;
      prevF = channel(s.y);
    }
  }
  void onStep(const lg::Model<double>&, const lg::State<double>& s, lg::Workspace<double>&,
              const lg::DenseOutput<double>& d) {
    take(s);
    if (!channel) return;
    const double f1 = channel(s.y);
    if (prevF < 0 && f1 >= 0) {
      // The step may have ended on an event: the dense output covers [t0, s.t] either way.
      double a = prevT, b = s.t;
      for (int it = 0; it < 200 && b - a > 1e-13; ++it) {
        const double c = 0.5 * (a + b);
        d.at(c, tmp);
        (channel(tmp) < 0 ? a : b) = c;
      }
      upCrossings.push_back(0.5 * (a + b));
    }
    prevT = s.t;
    prevF = f1;
  }
  void onEvent(const lg::Model<double>&, const lg::State<double>&, lg::Workspace<double>&, int) {}
  bool stopRequested() const { return false; }

  // Mean period from the first to the last upward crossing.
  double period() const {
    REQUIRE(upCrossings.size() >= 2);
    return (upCrossings.back() - upCrossings.front()) / double(upCrossings.size() - 1);
  }
};

}  // namespace lgtest
