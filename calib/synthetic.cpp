// Synthetic drop-test measurements (synthetic.hpp).
#include "calib/synthetic.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "calib/residuals.hpp"
#include "sim/drop/run.hpp"

namespace lg::calib {

double GaussianNoise::uniform() { return static_cast<double>((engine_() >> 11) + 1) * 0x1.0p-53; }

double GaussianNoise::next() {
  if (haveSpare_) {
    haveSpare_ = false;
    return spare_;
  }
  const double u1 = uniform(), u2 = uniform();
  const double r = std::sqrt(-2 * std::log(u1)), a = 2 * M_PI * u2;
  spare_ = r * std::sin(a);
  haveSpare_ = true;
  return r * std::cos(a);
}

std::string syntheticCsv(const Scene& scene, const SyntheticSpec& spec) {
  if (!(spec.rate > 0) || !(spec.end > spec.start) || spec.channels.empty())
    throw std::invalid_argument("a synthetic measurement needs a rate > 0, end > start and a channel");
  // A calibration of one measurement, to simulate it exactly as `calibrate` does.
  Calibration c;
  c.scene = scene;
  Measurement m;
  m.name = spec.dropCase.name;
  m.dropCase = spec.dropCase;
  const std::vector<Column> history = historyColumns(scene);
  for (const auto& sc : spec.channels) {
    Channel ch;
    ch.name = sc.name;
    for (std::size_t h = 0; h < history.size(); ++h)
      if (history[h].name == sc.name) ch.historyColumn = static_cast<int>(h);
    if (ch.historyColumn < 0) throw std::invalid_argument("'" + sc.name + "' is not a channel of the scene's time histories");
    m.channels.push_back(ch);
  }
  for (long k = 0;; ++k) {
    const double t = spec.start + static_cast<double>(k) / spec.rate;
    if (t > spec.end) break;
    m.t.push_back(t);
  }
  if (m.t.back() - spec.touchdown > spec.dropCase.duration)
    throw std::invalid_argument("the last sample lies beyond the end of the drop (its duration)");
  c.measurements.push_back(m);
  const Simulated s = simulateMeasurement(c, 0, scene, spec.touchdown);
  if (!s.ok) throw std::runtime_error("the drop failed: " + s.message);
  if (spec.digits < 1 || spec.digits > 17) throw std::invalid_argument("digits must be in [1, 17]");
  auto num = [&](double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.*g", spec.digits, v);
    return std::string(b);
  };
  GaussianNoise noise(spec.seed);
  std::ostringstream o;
  o << spec.timeColumn;
  for (const auto& sc : spec.channels) o << "," << sc.csvColumn;
  o << "\n";
  for (std::size_t i = 0; i < m.t.size(); ++i) {
    o << num(m.t[i]);
    for (std::size_t k = 0; k < spec.channels.size(); ++k) {
      const double sigma = spec.channels[k].sigma;
      o << "," << num(s.y[k][i] + (sigma > 0 ? sigma * noise.next() : 0.0));
    }
    o << "\n";
  }
  return o.str();
}

}  // namespace lg::calib
