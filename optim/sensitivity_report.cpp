// report.md, the pictures and writing every output of a sensitivity study (sensitivity_report.hpp).
#include "optim/sensitivity_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "sim/core/format.hpp"
#include "sim/scene/parameters.hpp"  // parameterUnit
#include "sim/io/files.hpp"
#include "sim/io/plots.hpp"
#include "sim/drop/metrics.hpp"

namespace fs = std::filesystem;

namespace lg::optim {
// The parts of a one-sidedness note (drop_gradient.hpp: its reasons joined by "; ") that hold for the
// derivative in 'path': the lift plateau's is one-sided in the lift ratio alone, the others in every
// parameter.
std::string oneSidedFor(const std::string& note, const std::string& path) {
  const bool lift = path.size() >= 11 && path.compare(path.size() - 11, 11, ".lift_ratio") == 0;
  std::string out;
  for (std::size_t a = 0; a < note.size();) {
    std::size_t b = note.find("; ", a);
    if (b == std::string::npos) b = note.size();
    const std::string part = note.substr(a, b - a);
    if (lift || part.find("its derivative in the lift ratio is one-sided") == std::string::npos)
      out += (out.empty() ? "" : "; ") + part;
    a = b + 2;
  }
  return out;
}

namespace {

// Marks where a picture goes in the markdown (a control character: never in a name of the study).
constexpr char kMark = '\x01';

// A gnuplot single-quoted string.
std::string gpString(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}
// A gnuplot data-file string column.
std::string dataString(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' || c == '\n' ? '_' : c;
  return q + "\"";
}

std::string interval(const uq::Interval& i) { return "[" + shortNumber(i.lo, 3) + ", " + shortNumber(i.hi, 3) + "]"; }

// Outputs of one metric: indices into r.outputs (its cases in order).
std::vector<std::size_t> outputsOf(const SensitivityResult& r, const std::string& metric) {
  std::vector<std::size_t> k;
  for (std::size_t j = 0; j < r.outputs.size(); ++j)
    if (r.outputs[j].metric == metric) k.push_back(j);
  return k;
}

std::string failureSection(const SensitivityResult& r) {
  std::ostringstream m;
  m << "## Failed runs\n\nA run is one design on every case of interest; a case that fails in it (the scene rejects "
       "the design, or the simulation stops) gives NaN outputs for that case only, and no estimator ever sees a NaN: "
       "the local method leaves the elasticities that need the run undefined, Morris drops the elementary effects "
       "with a failed end point, Sobol drops the whole block of the base point (A, B and every AB^i) from that "
       "output's estimate.\n\n| method | runs | failed runs |";
  const std::size_t nc = r.settings.cases.size();
  for (std::size_t c = 0; c < nc; ++c) m << " " << r.outputs[c].caseName << " |";
  m << "\n|---|---|---|";
  for (std::size_t c = 0; c < nc; ++c) m << "---|";
  m << "\n";
  auto row = [&](const char* name, std::size_t runs, const MethodFailures& f) {
    m << "| " << name << " | " << runs << " | " << f.runs << " |";
    for (std::size_t c = 0; c < nc; ++c) m << " " << (c < f.perCase.size() ? f.perCase[c] : 0) << " |";
    m << "\n";
  };
  if (r.local) row("local", r.local->runs.size(), r.localFailures);
  if (r.morris) row("morris", r.morris->runs.size(), r.morrisFailures);
  if (r.sobol) row("sobol", r.sobol->runs.size(), r.sobolFailures);
  std::size_t shown = 0;
  for (const auto* f : {&r.localFailures, &r.morrisFailures, &r.sobolFailures})
    for (const auto& x : f->list) {
      if (shown++ == 0) m << "\nWhere (the first 20; every one is in indices.json and the samples CSV):\n\n";
      if (shown <= 20) m << "- run " << x.run << " (" << x.where << "): " << x.message << "\n";
    }
  if (shown == 0) m << "\nNo run failed.\n";
  return m.str() + "\n";
}

std::string localSection(const Study& s, const SensitivityResult& r) {
  std::ostringstream m;
  const LocalStudy& L = *r.local;
  m << "## Local sensitivities (elasticities at the baseline)\n\nE = d ln f / d ln x = (x / f) df/dx at the "
       "variables' baseline values; derivative source: **"
    << derivativeSource(r.settings) << "**"
    << (L.exact ? " (one run with the derivatives of every output)"
                : " (E = (f(x(1+h)) - f(x(1-h))) / (2 h f(x)), " + std::to_string(L.runs.size()) + " designs, 2d+1)")
    << ". E = 0.5 means +1 % of the parameter gives +0.5 % of the metric.\n\n";
  for (const std::string& metric : r.settings.metrics) {
    const auto ks = outputsOf(r, metric);
    m << "### " << metric << "\n\n| variable |";
    for (std::size_t k : ks) m << " " << r.outputs[k].caseName << " |";
    m << "\n|---|";
    for (std::size_t i = 0; i < ks.size(); ++i) m << "---|";
    m << "\n| *baseline [" << r.outputs[ks[0]].unit << "]* |";
    for (std::size_t k : ks) m << " *" << shortNumber(L.outputs[k].baseline) << "* |";
    m << "\n";
    // One footnote per distinct one-sidedness note, numbered in the order they first apply; each cell is
    // marked only where its note applies to its variable (a kink in the lift ratio alone marks lift_ratio).
    std::vector<std::string> notes;
    std::vector<std::vector<std::string>> noteCells;  // per note: "case (variable)" where it applies
    auto noteFor = [&](std::size_t k, const std::string& path) {
      return k < L.oneSided.size() ? oneSidedFor(L.oneSided[k], path) : std::string();
    };
    auto numberOf = [&](const std::string& note) -> std::size_t {
      if (note.empty()) return 0;
      const auto it = std::find(notes.begin(), notes.end(), note);
      if (it != notes.end()) return static_cast<std::size_t>(it - notes.begin()) + 1;
      notes.push_back(note);
      noteCells.emplace_back();
      return notes.size();
    };
    for (std::size_t i = 0; i < s.variables.size(); ++i) {
      m << "| " << s.variables[i].path << " |";
      for (std::size_t k : ks) {
        const uq::Elasticities& e = L.outputs[k];
        const std::size_t n = numberOf(noteFor(k, s.variables[i].path));
        if (n) noteCells[n - 1].push_back(r.outputs[k].caseName + " (" + s.variables[i].path + ")");
        m << " " << (e.why[i].empty() ? shortNumber(e.E[i], 4) : "undefined: " + e.why[i])
          << (n ? " (" + std::to_string(n) + ")" : "") << " |";
      }
      m << "\n";
    }
    for (std::size_t n = 0; n < notes.size(); ++n) {
      m << "\n(" << n + 1 << ") one-sided in ";
      for (std::size_t c = 0; c < noteCells[n].size(); ++c) m << (c ? ", " : "") << noteCells[n][c];
      m << ": " << notes[n] << "\n";
    }
    m << "\n" << kMark << "tornado_" << safeFileStem(metric) << kMark << "\n\n";
  }
  return m.str();
}

std::string morrisSection(const Study& s, const SensitivityResult& r) {
  std::ostringstream m;
  const MorrisStudy& M = *r.morris;
  m << "## Morris screening\n\n" << M.design.levels << "-level grid in the scaled variables, Delta = "
    << shortNumber(M.design.delta, 4) << ", r = " << M.design.r << " trajectories, " << M.runs.size()
    << " designs (r(d+1)); seed " << r.settings.seed << ". Elementary effects in the metric's unit per whole range of "
    << "the variable; mu* (mean |EE|) ranks the influence, sigma large against mu* means interactions or a "
    << "non-linear response; the " << shortNumber(100 * r.settings.confidence, 3) << " % interval on mu* is a "
    << "seeded bootstrap (" << r.settings.resamples << " resamples).\n\n";
  for (const std::string& metric : r.settings.metrics) {
    const auto ks = outputsOf(r, metric);
    m << "### " << metric << " [" << r.outputs[ks[0]].unit << "]\n\n| variable |";
    for (std::size_t k : ks) m << " " << r.outputs[k].caseName << ": mu* [interval], sigma, mu |";
    m << "\n|---|";
    for (std::size_t i = 0; i < ks.size(); ++i) m << "---|";
    m << "\n";
    for (std::size_t i = 0; i < s.variables.size(); ++i) {
      m << "| " << s.variables[i].path << " |";
      for (std::size_t k : ks) {
        const uq::MorrisIndices& x = M.outputs[k];
        m << " " << shortNumber(x.muStar[i], 4) << " " << interval(x.muStarCi[i]) << ", " << shortNumber(x.sigma[i], 4)
          << ", " << shortNumber(x.mu[i], 4) << " |";
      }
      m << "\n";
    }
    m << "\n" << kMark << "morris_" << safeFileStem(metric) << kMark << "\n\n";
  }
  return m.str();
}

// S1 / ST of every output and variable at N/8, N/4, N/2, N.
std::string convergenceSection(const Study& s, const SensitivityResult& r) {
  std::ostringstream m;
  const SobolStudy& S = *r.sobol;
  const std::size_t d = s.variables.size();
  m << "### Convergence: S1 / ST against N\n\n| metric | case | variable |";
  for (std::size_t n : S.convergenceN) m << " N = " << n << " |";
  m << "\n|---|---|---|";
  for (std::size_t n = 0; n < S.convergenceN.size(); ++n) m << "---|";
  m << "\n";
  for (std::size_t k = 0; k < r.outputs.size(); ++k)
    for (std::size_t i = 0; i < d; ++i) {
      m << "| " << r.outputs[k].metric << " | " << r.outputs[k].caseName << " | " << s.variables[i].path << " |";
      for (std::size_t n = 0; n < S.convergenceN.size(); ++n)
        m << " " << shortNumber(S.convergence[n][k].S1[i], 3) << " / " << shortNumber(S.convergence[n][k].ST[i], 3) << " |";
      m << "\n";
    }
  return m.str();
}

std::string sobolSection(const Study& s, const SensitivityResult& r, const std::vector<std::string>& warnings) {
  std::ostringstream m;
  const SobolStudy& S = *r.sobol;
  const std::size_t d = s.variables.size();
  m << "## Sobol indices\n\nSaltelli scheme on a Sobol sequence (Boost.Random, Joe-Kuo directions) of dimension 2d = "
    << 2 * d << " with a random digital shift (seed " << r.settings.seed << "): N = " << S.design.n
    << " base points, **N(d+2) = " << S.design.n << " x " << d + 2 << " = " << S.runs.size() << " designs**, "
    << S.runs.size() * r.settings.cases.size() << " drops. First order S1 by Saltelli (2010), total ST by Jansen; "
    << shortNumber(100 * r.settings.confidence, 3) << " % intervals by a seeded bootstrap over the base points ("
    << r.settings.resamples << " resamples). ST - S1 is the share of the variance from the variable's interactions.\n\n";
  for (const std::string& metric : r.settings.metrics) {
    const auto ks = outputsOf(r, metric);
    m << "### " << metric << "\n\n| variable |";
    for (std::size_t k : ks) m << " " << r.outputs[k].caseName << ": S1 [interval] | ST [interval] |";
    m << "\n|---|";
    for (std::size_t i = 0; i < ks.size(); ++i) m << "---|---|";
    m << "\n";
    for (std::size_t i = 0; i < d; ++i) {
      m << "| " << s.variables[i].path << " |";
      for (std::size_t k : ks) {
        const uq::SobolIndices& x = S.outputs[k];
        m << " " << shortNumber(x.S1[i], 3) << " " << (x.S1ci.empty() ? "" : interval(x.S1ci[i])) << " | "
          << shortNumber(x.ST[i], 3) << " " << (x.STci.empty() ? "" : interval(x.STci[i])) << " |";
      }
      m << "\n";
    }
    m << "| *sum S1; mean, std [" << r.outputs[ks[0]].unit << "]* |";
    for (std::size_t k : ks) {
      const uq::SobolIndices& x = S.outputs[k];
      double sum = 0;
      for (double v : x.S1) sum += v;
      m << " *" << shortNumber(sum, 3) << "* | *" << shortNumber(x.mean, 5) << ", " << shortNumber(std::sqrt(x.variance), 3)
        << (x.constant ? " (constant)" : "") << "* |";
    }
    m << "\n\n" << kMark << "sobol_" << safeFileStem(metric) << kMark << "\n\n";
  }
  m << convergenceSection(s, r) << "\n### Warnings\n\n";
  if (warnings.empty()) m << "None: every interval is narrower than the index it bounds.\n";
  for (const auto& w : warnings) m << "- " << w << "\n";
  return m.str() + "\n";
}

// ---- pictures -------------------------------------------------------------------------------------
// One figure per metric and method, one panel per case of interest, variables on the vertical axis.
struct Figure {
  std::string stem, title;
  std::string data;    // gnuplot data: one block per case (separated by two blank lines)
  std::string panel;   // the plot command of a panel, with @I@ for the block index
  std::string setup;   // gnuplot settings for every panel
};

Figure tornadoFigure(const Study& s, const SensitivityResult& r, const std::string& metric) {
  Figure f;
  f.stem = "tornado_" + safeFileStem(metric);
  f.title = "Local sensitivities of " + metric + ": elasticity d ln f / d ln x (" + derivativeSource(r.settings) + ")";
  f.setup = "set xlabel 'elasticity [-]'\nset style fill solid 0.8 border -1\nset grid x\nset yzeroaxis lt -1\n";
  f.panel = "plot 'DATA' index @I@ using (0):0:(($2<0)?$2:0):(($2<0)?0:$2):($0-0.35):($0+0.35):ytic(1) "
            "with boxxyerror lc rgb '#1f77b4' notitle";
  // A tornado: the variables by their largest |E| over the cases, the largest on top.
  const auto ks = outputsOf(r, metric);
  std::vector<std::pair<double, std::size_t>> order;
  for (std::size_t i = 0; i < s.variables.size(); ++i) {
    double big = 0;
    for (std::size_t k : ks)
      if (std::isfinite(r.local->outputs[k].E[i])) big = std::max(big, std::abs(r.local->outputs[k].E[i]));
    order.push_back({big, i});
  }
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t k : ks) {
    f.data += "# " + r.outputs[k].caseName + ": variable elasticity[-] (by the largest |elasticity| of any case)\n";
    for (const auto& [big, i] : order)
      f.data += dataString(s.variables[i].path) + " " + plotNumber(r.local->outputs[k].E[i]) + "\n";
    f.data += "\n\n";
  }
  return f;
}

Figure morrisFigure(const Study& s, const SensitivityResult& r, const std::string& metric) {
  Figure f;
  const std::string unit = findMetric(metric) ? findMetric(metric)->unit : "-";
  f.stem = "morris_" + safeFileStem(metric);
  f.title = "Morris screening of " + metric + ": mu* against sigma (elementary effects per range of the variable)";
  f.setup = "set xlabel 'mu* [" + unit + "]'\nset ylabel 'sigma [" + unit + "]'\nset grid\nset xrange [0:*]\nset yrange [0:*]\n";
  f.panel = "plot 'DATA' index @I@ using 2:5:3:4 with xerrorbars pt 7 lc rgb '#1f77b4' notitle, "
            "'' index @I@ using 2:5:1 with labels offset 0.8,0.6 left font ',8' notitle";
  for (std::size_t k : outputsOf(r, metric)) {
    const uq::MorrisIndices& m = r.morris->outputs[k];
    f.data += "# " + r.outputs[k].caseName + ": variable mu*[" + unit + "] mu*_lo mu*_hi sigma[" + unit + "]\n";
    for (std::size_t i = 0; i < s.variables.size(); ++i)
      f.data += dataString(s.variables[i].path) + " " + plotNumber(m.muStar[i]) + " " + plotNumber(m.muStarCi[i].lo) +
                " " + plotNumber(m.muStarCi[i].hi) + " " + plotNumber(m.sigma[i]) + "\n";
    f.data += "\n\n";
  }
  return f;
}

Figure sobolFigure(const Study& s, const SensitivityResult& r, const std::string& metric) {
  Figure f;
  f.stem = "sobol_" + safeFileStem(metric);
  f.title = "Sobol indices of " + metric + ": first order S1 and total ST with their bootstrap intervals";
  f.setup = "set xlabel 'index [-]'\nset style fill solid 0.8 border -1\nset grid x\nset xrange [0:1]\nset key below horizontal\n";
  f.panel = "plot 'DATA' index @I@ using (0):($0+0.18):(0):2:($0+0.02):($0+0.34):ytic(1) with boxxyerror lc rgb '#1f77b4' title 'S1', "
            "'' index @I@ using 2:($0+0.18):3:4 with xerrorbars pt 0 lc rgb 'black' notitle, "
            "'' index @I@ using (0):($0-0.18):(0):5:($0-0.34):($0-0.02) with boxxyerror lc rgb '#ff7f0e' title 'ST', "
            "'' index @I@ using 5:($0-0.18):6:7 with xerrorbars pt 0 lc rgb 'black' notitle";
  for (std::size_t k : outputsOf(r, metric)) {
    const uq::SobolIndices& x = r.sobol->outputs[k];
    f.data += "# " + r.outputs[k].caseName + ": variable S1 S1_lo S1_hi ST ST_lo ST_hi [-]\n";
    for (std::size_t i = 0; i < s.variables.size(); ++i) {
      const uq::Interval none{NAN, NAN}, a = x.S1ci.empty() ? none : x.S1ci[i], b = x.STci.empty() ? none : x.STci[i];
      f.data += dataString(s.variables[i].path) + " " + plotNumber(x.S1[i]) + " " + plotNumber(a.lo) + " " +
                plotNumber(a.hi) + " " + plotNumber(x.ST[i]) + " " + plotNumber(b.lo) + " " + plotNumber(b.hi) + "\n";
    }
    f.data += "\n\n";
  }
  return f;
}

std::string figureScript(const Figure& f, const SensitivityResult& r) {
  const std::size_t nc = r.settings.cases.size();
  std::ostringstream g;
  g << "reset\nset terminal pngcairo size " << 420 * nc + 120 << "," << 140 + 36 * 10 << " noenhanced\n";
  g << "set output '" << f.stem << ".png'\n";
  g << "set multiplot layout 1," << nc << " title " << gpString(f.title) << "\n" << f.setup;
  g << "set xtics rotate by -30 font ',9'\nset format x '%g'\n";
  for (std::size_t c = 0; c < nc; ++c) {
    std::string p = f.panel;
    for (std::size_t at; (at = p.find("@I@")) != std::string::npos;) p.replace(at, 3, std::to_string(c));
    for (std::size_t at; (at = p.find("DATA")) != std::string::npos;) p.replace(at, 4, f.stem + ".dat");
    g << "set title " << gpString(r.outputs[c].caseName) << "\n" << p << "\n";
  }
  return g.str() + "unset multiplot\n";
}

}  // namespace

std::vector<std::string> sobolWarnings(const Study& s, const SensitivityResult& r) {
  std::vector<std::string> w;
  if (!r.sobol) return w;
  for (std::size_t k = 0; k < r.outputs.size(); ++k) {
    const uq::SobolIndices& x = r.sobol->outputs[k];
    const std::string out = r.outputs[k].label();
    if (!x.estimated) {
      w.push_back(out + ": not estimated (fewer than 2 complete blocks)");
      continue;
    }
    if (!x.dropped.empty())
      w.push_back(out + ": " + std::to_string(x.dropped.size()) + " of " + std::to_string(x.blocks) +
                  " blocks dropped (failed runs)");
    for (std::size_t i = 0; i < s.variables.size() && !x.S1ci.empty(); ++i)
      for (int which = 0; which < 2; ++which) {
        const double v = which ? x.ST[i] : x.S1[i];
        const uq::Interval& ci = which ? x.STci[i] : x.S1ci[i];
        if (ci.width() > std::abs(v))
          w.push_back(std::string(which ? "ST" : "S1") + " of " + s.variables[i].path + " for " + out + " = " +
                      shortNumber(v, 3) + ": its interval " + interval(ci) + " is wider than the index");
      }
  }
  return w;
}

std::string sensitivityMarkdown(const Study& s, const SensitivityResult& r, const std::string& note) {
  std::ostringstream m;
  m << "# Sensitivity study: " << s.name << "\n\n- study file: `" << s.file << "`\n- scene: `" << s.sceneFile << "`\n";
  m << "- cases of interest:";
  for (std::size_t c = 0; c < r.settings.cases.size(); ++c) m << (c ? "," : "") << " " << r.outputs[c].caseName;
  m << "\n- metrics of interest:";
  for (std::size_t k = 0; k < r.settings.metrics.size(); ++k)
    m << (k ? "," : "") << " " << r.settings.metrics[k] << " [" << findMetric(r.settings.metrics[k])->unit << "]";
  m << "\n- methods:" << (r.local ? " local" : "") << (r.morris ? " morris" : "") << (r.sobol ? " sobol" : "")
    << "; seed " << r.settings.seed << "; " << r.designs << " designs, " << r.drops << " drops in all\n";
  m << "- drop-test solver: " << s.solverChoice << "\n";
  m << "- the global methods sample each variable uniformly in its scaled coordinate: uniform between its bounds, "
       "log-uniform where `log = true`\n\n";
  m << "| variable | unit | lower | upper | scale | baseline |\n|---|---|---|---|---|---|\n";
  for (const auto& v : s.variables)
    m << "| " << v.path << " | " << parameterUnit(v.path) << " | " << shortNumber(v.lower) << " | " << shortNumber(v.upper)
      << " | " << (v.log ? "log" : "linear") << " | " << shortNumber(v.initial) << " |\n";
  m << "\n" << failureSection(r);
  if (r.local) m << localSection(s, r);
  if (r.morris) m << morrisSection(s, r);
  if (r.sobol) m << sobolSection(s, r, sobolWarnings(s, r));
  m << "## Files\n\n`indices.json`; `indices_<method>.csv` (every index); `samples_<method>.csv` (every run: design "
       "and outputs, units in the headers)";
  if (r.sobol) m << "; `convergence_sobol.csv`";
  m << "; `plots/` (gnuplot data and scripts" << (note.empty() ? " and pictures)" : ")") << ".\n";
  if (!note.empty()) m << "\n" << note << "\n";
  // Pictures: each marker becomes its image, or nothing when there are none.
  std::string text = m.str();
  for (std::size_t at; (at = text.find(kMark)) != std::string::npos;) {
    const std::size_t end = text.find(kMark, at + 1);
    const std::string stem = text.substr(at + 1, end - at - 1);
    text.replace(at, end + 1 - at, note.empty() ? "![" + stem + "](plots/" + stem + ".png)" : "");
  }
  return text;
}

SensitivityFiles writeSensitivity(const Study& s, const SensitivityResult& r, const std::string& dir, bool plots,
                                  const Provenance* provenance) {
  SensitivityFiles out;
  const fs::path d(dir), pd = d / "plots";
  fs::create_directories(pd);
  auto put = [&](const fs::path& p, const std::string& text) {
    writeFileAtomic(p.string(), text);
    out.written.push_back(fs::relative(p, d).string());
  };
  std::vector<std::string> methods;
  if (r.local) methods.push_back("local");
  if (r.morris) methods.push_back("morris");
  if (r.sobol) methods.push_back("sobol");
  for (const std::string& method : methods) {
    put(d / ("samples_" + method + ".csv"), samplesCsv(s, r, method));
    put(d / ("indices_" + method + ".csv"), indicesCsv(s, r, method));
  }
  if (r.sobol) put(d / "convergence_sobol.csv", convergenceCsv(s, r));
  put(d / "indices.json", stampJson(sensitivityJson(s, r), provenance));
  std::string script;
  for (const std::string& metric : r.settings.metrics) {
    std::vector<Figure> figs;
    if (r.local) figs.push_back(tornadoFigure(s, r, metric));
    if (r.morris) figs.push_back(morrisFigure(s, r, metric));
    if (r.sobol) figs.push_back(sobolFigure(s, r, metric));
    for (const Figure& f : figs) {
      put(pd / (f.stem + ".dat"), f.data);
      script += figureScript(f, r);
    }
  }
  put(pd / "plots.gp", script);
  std::string note;
  if (!plots) note = "Pictures were not requested: run `gnuplot plots.gp` in `plots/` to draw them.";
  else if (!haveGnuplot()) note = "gnuplot was not found: run `gnuplot plots.gp` in `plots/` to draw the pictures.";
  else if (std::system(("cd '" + pd.string() + "' && gnuplot plots.gp > gnuplot.log 2>&1").c_str()) != 0)
    note = "gnuplot failed (see `plots/gnuplot.log`); the data and the script are in `plots/`.";
  out.pictures = note.empty();
  if (!note.empty() && plots) out.warnings.push_back(note);
  for (const auto& w : sobolWarnings(s, r)) out.warnings.push_back(w);
  put(d / "report.md", stampMarkdown(sensitivityMarkdown(s, r, note), provenance));
  return out;
}

}  // namespace lg::optim
