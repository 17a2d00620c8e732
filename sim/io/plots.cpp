// Drop-test pictures through gnuplot (plots.hpp).
#include "sim/io/plots.hpp"

#include <cctype>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <filesystem>
#include <sstream>
#include <vector>

#include "sim/io/files.hpp"

namespace lg {
namespace {

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}
std::string label(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

// A gnuplot single-quoted string: quotes doubled.
std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("''") : std::string(1, c);
  return q + "'";
}

// The channels a figure draws, by row: t h P_y s P_a delta (NaN where the scene has none).
struct Rows {
  std::vector<double> t, h, Py, s, Pa, delta, Px;
  bool drag = false;  // the run has a drag load (a tyre that declares mu_x)
};
Rows rowsOf(const CaseFigure& f, const CaseResult& r) {
  auto col = [&](const std::string& base, const std::string& element) {
    const int c = r.column(base);
    return c >= 0 ? c : r.column(base + "_" + element);
  };
  const int ch = col("h", ""), cP = col("P_y", ""), cs = col("s", f.strut), ca = col("P_a", f.strut),
            cd = col("delta", f.tyre), cx = col("P_x", f.tyre);
  Rows out;
  out.drag = cx >= 0;
  for (const Sample& x : r.samples) {
    auto v = [&](int c) { return c >= 0 ? x.values[c] : std::numeric_limits<double>::quiet_NaN(); };
    out.t.push_back(x.t);
    out.h.push_back(v(ch));
    out.Py.push_back(v(cP));
    out.s.push_back(v(cs));
    out.Pa.push_back(v(ca));
    out.delta.push_back(v(cd));
    out.Px.push_back(v(cx));
  }
  return out;
}

// The phases of a drop for the work diagrams: 0 the compression (up to the maximum of x), 1 the return
// stroke (until the tyres leave the ground or the strut is extended, or a second compression begins),
// 2 after it. A second compression is a rise of x by more than 1e-3 of its maximum above the lowest
// value since the turn: where Coulomb friction holds the strut at its turn, x stands still to round-off,
// and such a wiggle is no second compression.
std::vector<int> phases(const std::vector<double>& x, const std::vector<double>& back) {
  size_t iMax = 0;
  for (size_t i = 0; i < x.size(); ++i)
    if (x[i] > x[iMax]) iMax = i;
  std::vector<int> p(x.size(), 2);
  for (size_t i = 0; i <= iMax && i < x.size(); ++i) p[i] = 0;
  if (x.empty()) return p;
  const double rise = 1e-3 * std::abs(x[iMax]);
  double lowest = x[iMax];
  for (size_t i = iMax + 1; i < x.size(); ++i) {  // up to lift-off, or the turn into a second compression
    lowest = std::min(lowest, x[i]);
    if (x[i] > lowest + rise) break;
    p[i] = 1;
    if (!(back[i] > 0)) break;
  }
  return p;
}

// Columns: t h P_y s P_a delta gear-phase strut-phase (phases above: the gear's by h and P_y, the
// strut's by s).
std::string samplesData(const Rows& r) {
  const std::vector<int> gear = phases(r.h, r.Py), strut = phases(r.s, r.s);
  std::ostringstream d;
  d << "# t[s] h[m] P_y[N] s[m] P_a[N] delta[m] gear_phase strut_phase (0 compression, 1 return, 2 after the return) P_x[N]\n";
  const size_t n = r.t.size();
  for (size_t i = 0; i < n; ++i) {
    const std::string values = num(r.t[i]) + " " + num(r.h[i]) + " " + num(r.Py[i]) + " " + num(r.s[i]) + " " +
                               num(r.Pa[i]) + " " + num(r.delta[i]);
    const std::string px = " " + num(r.Px[i]);
    d << values << " " << gear[i] << " " << strut[i] << px << "\n";
    // the return starts where the compression ends
    if (i + 1 < n && (gear[i] == 0) != (gear[i + 1] == 0)) d << values << " 1 " << strut[i] << px << "\n";
    if (i + 1 < n && (strut[i] == 0) != (strut[i + 1] == 0)) d << values << " " << gear[i] << " 1" << px << "\n";
  }
  return d.str();
}

// The range of a channel over the compression and the return stroke.
void workRange(const std::vector<double>& x, const std::vector<double>& back, double& lo, double& hi) {
  const std::vector<int> p = phases(x, back);
  lo = 0;
  hi = 0;
  for (size_t i = 0; i < x.size(); ++i)
    if (p[i] < 2 && std::isfinite(x[i])) {
      lo = std::min(lo, x[i]);
      hi = std::max(hi, x[i]);
    }
}

// A POSIX shell single-quoted word.
std::string shellQuoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// A horizontal limit as a constant function: part of the legend and of the y autoscale.
std::string hline(double y, const char* colour, const std::string& name) {
  if (!std::isfinite(y)) return "";
  return ", " + num(y) + " with lines dt 2 lw 2 lc rgb '" + colour + "' title " + quoted(name + " " + label(y));
}
}  // namespace

bool haveGnuplot() {  // asked once per process (a shell each time otherwise; it does not come and go in a run)
  static const bool have = std::system("command -v gnuplot >/dev/null 2>&1") == 0;
  return have;
}

void CaseFigure::drawElementsOf(const Scene& scene) {
  if (!scene.roles.struts.empty()) strut = scene.model.forces[scene.roles.struts[0]].name;
  if (!scene.roles.tyres.empty()) tyre = scene.model.forces[scene.roles.tyres[0]].name;
}

PlotLimits sceneLimits(const Scene& scene) {
  PlotLimits l;
  if (!scene.roles.strokeLimits.empty()) l.strokeLimit = scene.roles.strokeLimits[0];
  if (!scene.roles.tyres.empty())
    l.tyreLimit = std::get<Tyre<double>>(scene.model.forces[scene.roles.tyres[0]].type).deltaMax;
  return l;
}

bool drawCaseFigure(const CaseFigure& f, const std::string& dir, const std::string& stem, bool run, std::string* why) {
  namespace fs = std::filesystem;
  const fs::path d(dir);
  const Rows rows = rowsOf(f, *f.run);
  writeFileAtomic((d / (stem + ".dat")).string(), samplesData(rows));
  const bool base = f.baseline != nullptr;
  const Rows baseline = base ? rowsOf(f, *f.baseline) : Rows{};
  if (base) writeFileAtomic((d / (stem + "_baseline.dat")).string(), samplesData(baseline));
  const std::string dat = quoted(stem + ".dat"), bdat = quoted(stem + "_baseline.dat");
  const PlotLimits& L = f.limits;
  std::ostringstream gp;
  // (a fourth row with the drag load where a tyre declares mu_x: wheel spin-up)
  gp << "set terminal pngcairo size 1400," << (rows.drag ? 1700 : 1300) << " noenhanced font ',10'\n";
  gp << "set output " << quoted(stem + ".png") << "\n";
  // Headroom above every curve and limit line for the legend, which is opaque: labels never sit on a curve.
  gp << "set multiplot layout " << (rows.drag ? 4 : 3) << ",2 title " << quoted(f.title) << "\nset grid\nset key top right opaque\n"
     << "set offsets 0, 0, graph 0.22, 0\n";
  auto series = [&](const std::string& x, const std::string& y, int phaseColumn) {
    const bool split = phaseColumn > 0;
    const std::string ph = "$" + std::to_string(phaseColumn);
    std::ostringstream p;
    p << "plot ";
    if (split) {
      if (base)
        p << bdat << " using " << x << ":(" << ph << "<2?" << y.substr(1, y.size() - 2) << ":1/0) with lines lw 1.5 lc rgb '#9a9a9a' title "
          << quoted(f.baselineLabel) << ", ";
      p << dat << " using " << x << ":(" << ph << "==0?" << y.substr(1, y.size() - 2) << ":1/0) with lines lw 2 lc rgb '#1f77b4' title "
        << quoted(f.runLabel) << ", ";
      p << dat << " using " << x << ":(" << ph << "==1?" << y.substr(1, y.size() - 2) << ":1/0) with lines lw 2 lc rgb '#ff7f0e' title 'return'";
    } else {
      if (base) p << bdat << " using " << x << ":" << y << " with lines lw 1.5 lc rgb '#9a9a9a' title " << quoted(f.baselineLabel) << ", ";
      p << dat << " using " << x << ":" << y << " with lines lw 2 lc rgb '#1f77b4' " << (base ? "title " + quoted(f.runLabel) : "notitle");
    }
    return p.str();
  };
  const auto& M = f.run->metrics;
  const double kN = 1e-3;
  // P_y(t)
  gp << "set title 'vertical ground load P_y(t)'\nset xlabel 't [s]'\nset ylabel 'P_y [kN]'\n";
  gp << series("1", "($3/1000)", 0) << ", '+' using (" << num(M.t_peak_s) << "):(" << num(M.peak_load_N * kN)
     << ") every ::0::0 with points pt 7 ps 1.5 lc rgb '#d62728' title 'peak " << num(std::round(M.peak_load_N)) << " N'"
     << hline(L.loadLimit * kN, "#d62728", "limit load [kN]") << hline(L.loadUltimate * kN, "#8c564b", "ultimate load [kN]")
     << "\n";
  // P_y(h)
  // (the work diagrams' legends top left, in the headroom: their loops reach the right end low and high)
  gp << "set key top left\nset title 'work diagram P_y(h), compression and return stroke'\nset xlabel 'h [m]'\nset ylabel 'P_y [kN]'\n";
  double lo = 0, hi = 0;
  workRange(rows.h, rows.Py, lo, hi);
  if (base) {
    double blo = 0, bhi = 0;
    workRange(baseline.h, baseline.Py, blo, bhi);
    lo = std::min(lo, blo);
    hi = std::max(hi, bhi);
  }
  gp << "set xrange [" << num(lo - 0.03 * (hi - lo)) << ":" << num(hi + 0.03 * (hi - lo)) << "]\n";
  gp << series("2", "($3/1000)", 7) << hline(L.loadLimit * kN, "#d62728", "limit load [kN]")
     << hline(L.loadUltimate * kN, "#8c564b", "ultimate load [kN]") << "\nset autoscale x\nset key top right\n";
  // s(t)
  gp << "set title 'stroke s(t)'\nset xlabel 't [s]'\nset ylabel 's [m]'\n";
  gp << series("1", "($4)", 0) << hline(L.strokeLimit, "#d62728", "S_max (bottoming) [m]")
     << (L.strokeMargin != L.strokeLimit ? hline(L.strokeMargin, "#ff7f0e", "S_max - margin [m]") : "") << "\n";
  // P_a(s)
  gp << "set key top left\nset title 'strut work diagram P_a(s), compression and return stroke'\nset xlabel 's [m]'\nset ylabel 'P_a [kN]'\n";
  workRange(rows.s, rows.s, lo, hi);
  if (std::isfinite(L.strokeLimit)) hi = std::max(hi, L.strokeLimit);
  gp << "set xrange [" << num(lo - 0.03 * (hi - lo)) << ":" << num(hi + 0.03 * (hi - lo)) << "]\n";
  if (std::isfinite(L.strokeLimit)) {
    gp << "set arrow from first " << num(L.strokeLimit) << ", graph 0 to first " << num(L.strokeLimit)
       << ", graph 1 nohead dt 2 lw 2 lc rgb '#d62728'\n";
    if (std::isfinite(L.strokeMargin) && L.strokeMargin != L.strokeLimit)
      gp << "set arrow from first " << num(L.strokeMargin) << ", graph 0 to first " << num(L.strokeMargin)
         << ", graph 1 nohead dt 2 lw 2 lc rgb '#ff7f0e'\n";
  }
  gp << series("4", "($5/1000)", 8) << "\nunset arrow\nset autoscale x\nset key top right\n";
  // h(t)
  gp << "set title 'airframe travel h(t)'\nset xlabel 't [s]'\nset ylabel 'h [m]'\n";
  gp << series("1", "($2)", 0) << "\n";
  // delta(t)
  gp << "set title 'tyre deflection delta(t) (0 when airborne)'\nset xlabel 't [s]'\nset ylabel 'delta [m]'\n";
  gp << series("1", "($6>0?$6:0)", 0) << hline(L.tyreLimit, "#d62728", "tyre limit [m]") << "\n";
  if (rows.drag) {  // the drag load: spin-up (aft, positive) and spring-back (forward, negative), marked
    gp << "set title 'drag load P_x(t): wheel spin-up and spring-back'\nset xlabel 't [s]'\nset ylabel 'P_x [kN]'\n"
       << "set offsets 0, 0, graph 0.22, graph 0.1\n";
    gp << series("1", "($9/1000)", 0) << ", '+' using (" << num(M.t_drag_peak_s) << "):(" << num(M.drag_peak_N * kN)
       << ") every ::0::0 with points pt 7 ps 1.5 lc rgb '#d62728' title 'spin-up " << num(std::round(M.drag_peak_N)) << " N'"
       << ", '+' using (" << num(M.t_springback_s) << "):(" << num(-M.springback_peak_N * kN)
       << ") every ::0::0 with points pt 5 ps 1.5 lc rgb '#2ca02c' title 'spring-back " << num(std::round(M.springback_peak_N))
       << " N'\n";
  }
  gp << "unset multiplot\n";
  writeFileAtomic((d / (stem + ".gp")).string(), gp.str());
  if (!run) return true;
  return runGnuplot(d.string(), stem, why);
}

bool runGnuplot(const std::string& dir, const std::string& stem, std::string* why) {
  namespace fs = std::filesystem;
  if (!haveGnuplot()) {
    if (why) *why = "gnuplot is not installed (scripts/setup.sh installs gnuplot-nox)";
    return false;
  }
  const fs::path d(dir);
  const std::string cmd = "cd " + shellQuoted(d.string()) + " && gnuplot " + shellQuoted(stem + ".gp") + " > /dev/null 2> " +
                          shellQuoted(stem + ".gnuplot.log");
  if (std::system(cmd.c_str()) != 0) {
    if (why) *why = "gnuplot failed on " + (d / (stem + ".gp")).string() + " (see " + stem + ".gnuplot.log)";
    return false;
  }
  std::error_code ec;
  fs::remove(d / (stem + ".gnuplot.log"), ec);
  return true;
}

std::string gnuplotQuoted(const std::string& s) { return quoted(s); }

}  // namespace lg
