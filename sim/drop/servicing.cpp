// The static air curve, the static point and the servicing chart (servicing.hpp).
#include "sim/drop/servicing.hpp"

#include <algorithm>
#include <cmath>

#include "sim/drop/run.hpp"
#include "sim/forces/gas_spring.hpp"

namespace lg {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kCurvePoints = 101;     // strokes of the curve, 0 .. S_max
constexpr int kChartPoints = 41;      // extensions of the chart, S_max .. 0
constexpr double kWindow = 0.02;      // [-] of S_max: the rows a slope r(s) is fitted through

// The static law of the strut at the ambient temperature T: its gas spring with n_s in both chambers.
struct StaticGas {
  const ShockAbsorber<double>& a;
  double ns, Ts;
  double pressure(double s, double T) const {
    const double p01 = a.p01 * T / Ts, p02 = a.p02 * T / Ts;
    const GasSpring<double> g{p01, a.Omega0, ns, a.twoStage, p02, a.Omega02, ns};
    return g.pressure(s, a.area());
  }
  double force(double s, double T) const { return (pressure(s, T) - a.pAtm) * a.area(); }
};

// The gear's shortening g = h - delta against the stroke s over a drop's compression: (s, g) rows with s
// increasing. Empty with a message where the drop fails.
bool kinematics(const Scene& scene, std::vector<double>& s, std::vector<double>& g, std::string& why) {
  Scene sc = scene;
  sc.envelope.point = sc.envelope.nominal();
  DropCase d;
  d.name = "kinematics";
  d.sinkSpeed = 5.0;
  d.liftRatio = sc.roles.lifts.empty() ? 0.0 : 1.0;
  d.duration = 0.3;
  CaseOptions opt;
  opt.record = true;
  opt.outputInterval = 2e-4;
  const CaseResult r = runCase(sc, d, opt);
  if (!r.metrics.ok) {
    why = "the drop that measures the gear's kinematic ratio failed: " + r.metrics.message;
    return false;
  }
  const std::string sfx = sc.roles.struts.size() > 1 ? "_" + sc.model.forces[sc.roles.struts[0]].name : "";
  const std::string tfx = sc.roles.tyres.size() > 1 ? "_" + sc.model.forces[sc.roles.tyres[0]].name : "";
  const int cs = r.column("s" + sfx), ch = r.column("h"), cd = r.column("delta" + tfx);
  if (cs < 0 || ch < 0 || cd < 0) {
    why = "the gear's kinematic ratio needs a strut, an airframe and a tyre";
    return false;
  }
  for (const Sample& row : r.samples) {
    const double sv = row.values[cs];
    if (!s.empty() && sv < s.back() - 1e-9) break;  // the compression is over
    if (!s.empty() && !(sv > s.back() + 1e-9)) continue;
    s.push_back(sv);
    g.push_back(row.values[ch] - row.values[cd]);
  }
  if (s.size() < 10) {
    why = "the drop that measures the gear's kinematic ratio compressed the strut too little";
    return false;
  }
  return true;
}

// r(x) = dg/ds: the slope of the least-squares line through the rows within 'half' of x (NaN outside the
// rows, or with fewer than 3).
double slopeAt(const std::vector<double>& s, const std::vector<double>& g, double x, double half) {
  if (x < s.front() - 1e-12 || x > s.back() + 1e-12) return kNaN;
  const auto lo = std::lower_bound(s.begin(), s.end(), x - half), hi = std::upper_bound(s.begin(), s.end(), x + half);
  const long n = hi - lo;
  if (n < 3) return kNaN;
  double ms = 0, mg = 0;
  for (auto it = lo; it != hi; ++it) {
    ms += *it;
    mg += g[static_cast<size_t>(it - s.begin())];
  }
  ms /= static_cast<double>(n);
  mg /= static_cast<double>(n);
  double sxy = 0, sxx = 0;
  for (auto it = lo; it != hi; ++it) {
    const double dx = *it - ms;
    sxy += dx * (g[static_cast<size_t>(it - s.begin())] - mg);
    sxx += dx * dx;
  }
  return sxx > 0 ? sxy / sxx : kNaN;
}

}  // namespace

ServicingCurve servicingCurve(const Scene& scene, double mass) {
  ServicingCurve c;
  if (scene.roles.struts.empty()) {
    c.message = "the scene has no shock absorber";
    return c;
  }
  const int f = scene.roles.struts[0];
  const auto& a = std::get<ShockAbsorber<double>>(scene.model.forces[f].type);
  c.strut = scene.model.forces[f].name;
  c.strokeLimit = scene.roles.strokeLimits.empty() ? kNaN : scene.roles.strokeLimits[0];
  if (!std::isfinite(c.strokeLimit)) {
    c.message = "strut '" + c.strut + "' has no bottoming stop: the chart's extension is measured from it";
    return c;
  }
  const Envelope& env = scene.envelope;
  c.staticExponent = env.declared ? env.staticExponent : 1.0;
  c.serviceTemperature = env.declared ? env.serviceTemperature : kZeroCelsius + 15;
  c.chargeTolerance = env.declared ? env.chargeTolerance : 0.0;
  c.mass = mass;
  c.atmosphere = a.pAtm;
  const StaticGas gas{a, c.staticExponent, c.serviceTemperature};
  std::vector<double> ks, kg;
  if (!kinematics(scene, ks, kg, c.message)) return c;
  const double half = kWindow * c.strokeLimit, Wg = mass * scene.gravity;
  auto ratio = [&](double s) { return slopeAt(ks, kg, s, half); };
  for (int i = 0; i < kCurvePoints; ++i) {
    const double s = c.strokeLimit * i / (kCurvePoints - 1);
    c.stroke.push_back(s);
    c.pressure.push_back(gas.pressure(s, c.serviceTemperature));
    c.force.push_back(gas.force(s, c.serviceTemperature));
    c.ratio.push_back(ratio(s));
  }
  // The static point at T: the root of P_a(s) - W g r(s) (1), on the grid, then by bisection.
  auto staticStroke = [&](double T) {
    auto h = [&](double s) { return gas.force(s, T) - Wg * ratio(s); };
    const double h0 = h(0.0);
    if (h0 >= 0) return 0.0;  // the gas's preload holds the weight: the strut stays extended
    for (int i = 1; i < kCurvePoints; ++i) {
      double lo = c.strokeLimit * (i - 1) / (kCurvePoints - 1), hi = c.strokeLimit * i / (kCurvePoints - 1);
      double flo = h(lo), fhi = h(hi);
      if (!std::isfinite(flo) || !std::isfinite(fhi)) return kNaN;  // beyond the strokes the drop reached
      if (flo < 0 && fhi >= 0) {
        for (int it = 0; it < 60 && hi - lo > 1e-12; ++it) {
          const double mid = 0.5 * (lo + hi), fm = h(mid);
          (fm < 0 ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
      }
    }
    return kNaN;  // the weight bottoms the strut
  };
  c.staticStroke = staticStroke(c.serviceTemperature);
  if (!std::isfinite(c.staticStroke)) {
    c.message = "no static point within the strokes the gear's kinematic drop reached (0 .. " + std::to_string(ks.back()) +
                " m): the unit's weight at 1 g would bottom the strut";
    return c;
  }
  c.staticForce = gas.force(c.staticStroke, c.serviceTemperature);
  c.staticRatio = ratio(c.staticStroke);
  const double F = a.area();
  c.extendedToStatic = a.Omega0 / (a.Omega0 - c.staticStroke * F);
  c.staticToCompressed = (a.Omega0 - c.staticStroke * F) / (a.Omega0 - c.strokeLimit * F);
  for (int k = 0; k < kChartPoints; ++k) c.extension.push_back(c.strokeLimit * (kChartPoints - 1 - k) / (kChartPoints - 1));
  std::vector<double> temps{c.serviceTemperature};
  if (env.declared && env.temperatureRange) {
    temps = {env.cold, 0.5 * (env.cold + c.serviceTemperature), c.serviceTemperature, 0.5 * (c.serviceTemperature + env.hot),
             env.hot};
    std::sort(temps.begin(), temps.end());
    temps.erase(std::unique(temps.begin(), temps.end()), temps.end());
  }
  for (double T : temps) {
    ServicingChart ch;
    ch.temperature = T;
    for (double e : c.extension) {
      const double p = gas.pressure(c.strokeLimit - e, T);
      ch.pressure.push_back(p - a.pAtm);
      ch.low.push_back(p * (1 - c.chargeTolerance) - a.pAtm);
      ch.high.push_back(p * (1 + c.chargeTolerance) - a.pAtm);
    }
    const double s = staticStroke(T);
    if (std::isfinite(s)) {
      ch.staticExtension = c.strokeLimit - s;
      ch.staticPressure = gas.pressure(s, T) - a.pAtm;
    }
    c.chart.push_back(ch);
  }
  c.ok = true;
  return c;
}

}  // namespace lg
