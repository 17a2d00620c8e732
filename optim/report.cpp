// Study outputs: history, result.json, best.toml, report.md with gnuplot pictures (report.hpp).
#include "optim/report.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace lg::optim {
namespace {

std::string num(double v) {  // CSV / data-file number: exact round trip
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string shortNum(double v, int digits = 6) {  // for people
  if (!std::isfinite(v)) return "-";
  char b[40];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

std::string csvQuote(const std::string& s) {
  std::string q = "\"";
  for (char ch : s) {
    if (ch == '"') q += "\"\"";
    else if (ch == '\n' || ch == '\r') q += ' ';
    else q += ch;
  }
  return q + "\"";
}

std::string jsonString(const std::string& s) {
  std::string q = "\"";
  for (unsigned char ch : s) {
    switch (ch) {
      case '"': q += "\\\""; break;
      case '\\': q += "\\\\"; break;
      case '\n': q += "\\n"; break;
      case '\t': q += "\\t"; break;
      case '\r': q += "\\r"; break;
      default:
        if (ch < 0x20) {
          char b[8];
          std::snprintf(b, sizeof b, "\\u%04x", ch);
          q += b;
        } else {
          q += static_cast<char>(ch);
        }
    }
  }
  return q + "\"";
}

// Splits one CSV line (quotes as written by csvQuote).
std::vector<std::string> csvSplit(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted) {
      if (ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cur += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        cur += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += ch;
    }
  }
  out.push_back(cur);
  return out;
}

void writeFile(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  if (!f) throw std::runtime_error("cannot write '" + p.string() + "'");
  f << text;
  if (!f) throw std::runtime_error("cannot write '" + p.string() + "'");
}

std::string metricsJson(const CaseMetrics& m, const std::string& indent) {
  std::ostringstream o;
  o << "{\"name\": " << jsonString(m.name) << ", \"ok\": " << (m.ok ? "true" : "false")
    << ", \"message\": " << jsonString(m.message) << ",\n"
    << indent << " \"peak_load_N\": " << jsonNumber(m.peak_load_N) << ", \"t_peak_s\": " << jsonNumber(m.t_peak_s)
    << ", \"load_factor\": " << jsonNumber(m.load_factor) << ",\n"
    << indent << " \"stroke_max_m\": " << jsonNumber(m.stroke_max_m) << ", \"h_max_m\": " << jsonNumber(m.h_max_m)
    << ", \"tyre_deflection_max_m\": " << jsonNumber(m.tyre_deflection_max_m) << ",\n"
    << indent << " \"efficiency\": " << jsonNumber(m.efficiency)
    << ", \"strut_efficiency\": " << jsonNumber(m.strut_efficiency)
    << ", \"energy_absorbed_J\": " << jsonNumber(m.energy_absorbed_J) << ",\n"
    << indent << " \"energy_balance_error\": " << jsonNumber(m.energy_balance_error)
    << ", \"constraint_violation_max\": " << jsonNumber(m.constraint_violation_max)
    << ", \"strut_force_max_N\": " << jsonNumber(m.strut_force_max_N) << ",\n"
    << indent << " \"rebound_h_min_m\": " << jsonNumber(m.rebound_h_min_m)
    << ", \"bottomed\": " << (m.bottomed ? "true" : "false") << ", \"steps\": " << m.steps
    << ", \"rhs_evaluations\": " << m.rhs_evaluations << ", \"wall_time_s\": " << jsonNumber(m.wall_time_s) << "}";
  return o.str();
}

std::string objectiveKind(const Study& s) {
  return s.objective.kind == ObjectiveKind::MinPeakLoad ? "min_peak_load" : "max_efficiency";
}
std::string aggregateName(const Study& s) { return s.objective.aggregate == Aggregate::Max ? "max" : "weighted_sum"; }

std::string resultJson(const Study& s, const StudyResult& r, double wall) {
  const OptimizationResult& o = r.opt;
  const auto names = constraintNames(s);
  std::ostringstream j;
  j << "{\n";
  j << "  \"study\": " << jsonString(s.name) << ",\n";
  j << "  \"study_file\": " << jsonString(s.file) << ",\n";
  j << "  \"scene\": " << jsonString(s.sceneFile) << ",\n";
  j << "  \"algorithm\": {\"name\": " << jsonString(s.algorithm.name) << ", \"local\": " << jsonString(s.algorithm.local)
    << ", \"seed\": " << s.algorithm.seed << ", \"constraints\": "
    << jsonString(constraintNames(s).empty() ? "none" : describeConstraintHandling(s.algorithm.name, s.algorithm.penalty))
    << "},\n";
  j << "  \"objective\": {\"kind\": " << jsonString(objectiveKind(s)) << ", \"aggregate\": " << jsonString(aggregateName(s))
    << ", \"best\": " << jsonNumber(o.best.objective) << ", \"baseline\": " << jsonNumber(o.initial.objective)
    << ", \"scale\": " << jsonNumber(o.objectiveScale) << "},\n";
  j << "  \"feasible\": " << (o.feasible ? "true" : "false") << ",\n";
  j << "  \"variables\": [\n";
  for (size_t i = 0; i < s.variables.size(); ++i) {
    const Variable& v = s.variables[i];
    j << "    {\"path\": " << jsonString(v.path) << ", \"lower\": " << jsonNumber(v.lower) << ", \"upper\": "
      << jsonNumber(v.upper) << ", \"log\": " << (v.log ? "true" : "false") << ", \"initial\": " << jsonNumber(o.x0[i])
      << ", \"best\": " << jsonNumber(i < o.x.size() ? o.x[i] : NAN) << "}" << (i + 1 < s.variables.size() ? "," : "")
      << "\n";
  }
  j << "  ],\n";
  j << "  \"constraints\": [\n";
  for (size_t k = 0; k < names.size(); ++k) {
    const double gb = k < o.best.constraints.size() ? o.best.constraints[k] : NAN;
    const double g0 = k < o.initial.constraints.size() ? o.initial.constraints[k] : NAN;
    j << "    {\"name\": " << jsonString(names[k]) << ", \"best\": " << jsonNumber(gb) << ", \"baseline\": " << jsonNumber(g0)
      << ", \"rule\": \"<= 0\"}" << (k + 1 < names.size() ? "," : "") << "\n";
  }
  j << "  ],\n";
  j << "  \"best_evaluation\": " << o.bestIndex << ",\n";
  j << "  \"evaluations\": " << o.evaluations << ",\n";
  j << "  \"simulated_evaluations\": " << o.simulations << ",\n";
  j << "  \"wall_time_s\": " << jsonNumber(wall) << ",\n";
  j << "  \"nlopt\": {\"code\": " << o.nloptCode << ", \"name\": " << jsonString(o.nloptName)
    << ", \"reason\": " << jsonString(o.reason) << ", \"converged\": " << (o.converged ? "true" : "false") << "},\n";
  j << "  \"cases\": {\n    \"baseline\": [\n";
  for (size_t i = 0; i < r.baselineCases.size(); ++i)
    j << "      " << metricsJson(r.baselineCases[i], "      ") << (i + 1 < r.baselineCases.size() ? "," : "") << "\n";
  j << "    ],\n    \"best\": [\n";
  for (size_t i = 0; i < r.bestCases.size(); ++i)
    j << "      " << metricsJson(r.bestCases[i], "      ") << (i + 1 < r.bestCases.size() ? "," : "") << "\n";
  j << "    ]\n  }\n}\n";
  return j.str();
}

bool haveGnuplot() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

std::string gnuplotTerminal() {
  return std::system("gnuplot -e 'set terminal pngcairo' >/dev/null 2>&1") == 0 ? "pngcairo size 900,560"
                                                                                 : "png size 900,560";
}

std::string safeName(const std::string& n) {
  std::string s;
  for (char ch : n) s += (std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_') ? ch : '_';
  return s;
}

// Writes the data files and scripts under DIR/plots; runs gnuplot when present. Returns the markdown
// image lines (or the reason there are none).
std::string makePlots(const Study& s, const StudyResult& r, const std::vector<CaseResult>& base,
                      const std::vector<CaseResult>& best, const fs::path& dir, bool run, bool* made,
                      std::vector<std::string>* warnings) {
  *made = false;
  const fs::path pd = dir / "plots";
  fs::create_directories(pd);
  const bool maximize = s.objective.kind == ObjectiveKind::MaxEfficiency;
  // convergence
  {
    std::ostringstream d;
    d << "# eval objective feasible best_so_far_feasible\n";
    double bestSoFar = NAN;
    for (const auto& h : r.opt.history) {
      const double f = h.evaluation.ok ? h.evaluation.objective : NAN;
      if (h.feasible && (std::isnan(bestSoFar) || (maximize ? f > bestSoFar : f < bestSoFar))) bestSoFar = f;
      d << h.index << " " << num(f) << " " << (h.feasible ? 1 : 0) << " " << num(bestSoFar) << "\n";
    }
    writeFile(pd / "convergence.dat", d.str());
  }
  // work diagrams
  std::vector<std::string> workNames;
  for (size_t i = 0; i < base.size() && i < best.size(); ++i) {
    const std::string n = safeName(base[i].metrics.name);
    for (int which = 0; which < 2; ++which) {
      const auto& cr = which == 0 ? base[i] : best[i];
      std::ostringstream d;
      d << "# t[s] h[m] P_y[N] s[m] delta[m] P_a[N]\n";
      for (const auto& smp : cr.samples)
        d << num(smp.t) << " " << num(smp.h) << " " << num(smp.P_y) << " " << num(smp.s) << " " << num(smp.delta) << " "
          << num(smp.P_a) << "\n";
      writeFile(pd / ("work_" + n + (which == 0 ? "_baseline" : "_best") + ".dat"), d.str());
    }
    workNames.push_back(n);
  }
  // per-case figures
  {
    std::ostringstream d;
    d << "# i case peak_baseline[kN] peak_best[kN] eta_baseline eta_best\n";
    for (size_t i = 0; i < r.baselineCases.size() && i < r.bestCases.size(); ++i)
      d << i << " " << safeName(r.baselineCases[i].name) << " " << num(r.baselineCases[i].peak_load_N / 1e3) << " "
        << num(r.bestCases[i].peak_load_N / 1e3) << " " << num(r.baselineCases[i].efficiency) << " "
        << num(r.bestCases[i].efficiency) << "\n";
    writeFile(pd / "cases.dat", d.str());
  }
  std::ostringstream gp;
  gp << "set terminal " << (run ? gnuplotTerminal() : std::string("pngcairo size 900,560")) << "\n";
  gp << "set grid\nset key top right\n";
  gp << "set output 'convergence.png'\nset title 'Convergence: " << (maximize ? "efficiency" : "peak load [N]")
     << " per evaluation'\nset xlabel 'evaluation'\nset ylabel '" << (maximize ? "objective (efficiency)" : "objective [N]")
     << "'\n";
  gp << "plot 'convergence.dat' using 1:($3==1?$2:1/0) with points pt 7 ps 0.6 lc rgb '#1f77b4' title 'feasible', \\\n"
        "     '' using 1:($3==0?$2:1/0) with points pt 6 ps 0.6 lc rgb '#d62728' title 'infeasible', \\\n"
        "     '' using 1:4 with steps lw 2 lc rgb '#2ca02c' title 'best feasible so far'\n";
  for (const auto& n : workNames) {
    gp << "set output 'work_" << n << ".png'\nset title 'Work diagram P_y(h), case " << n
       << "'\nset xlabel 'h [m]'\nset ylabel 'P_y [kN]'\nset xrange [-0.02:*]\n";
    gp << "plot 'work_" << n << "_baseline.dat' using 2:($3/1000) with lines lw 2 lc rgb '#7f7f7f' title 'baseline', \\\n"
       << "     'work_" << n << "_best.dat' using 2:($3/1000) with lines lw 2 lc rgb '#1f77b4' title 'optimum'\n";
  }
  gp << "set output 'cases.png'\nset multiplot layout 1,2 title 'Per case: baseline vs optimum'\n"
        "set style data histograms\nset style histogram clustered gap 1\nset style fill solid 0.8 border -1\n"
        "set autoscale x\nset boxwidth 0.9\nset xtics rotate by -30\nset key top left\nunset xlabel\n"
        "set title 'peak load'\nset ylabel 'P_y,max [kN]'\nset yrange [0:*]\n"
        "plot 'cases.dat' using 3:xtic(2) title 'baseline' lc rgb '#7f7f7f', '' using 4 title 'optimum' lc rgb '#1f77b4'\n"
        "set title 'efficiency'\nset ylabel 'eta [-]'\nset yrange [0:1]\n"
        "plot 'cases.dat' using 5:xtic(2) title 'baseline' lc rgb '#7f7f7f', '' using 6 title 'optimum' lc rgb '#1f77b4'\n"
        "unset multiplot\n";
  writeFile(pd / "plots.gp", gp.str());
  if (!run) return "";
  const std::string cmd = "cd '" + pd.string() + "' && gnuplot plots.gp > gnuplot.log 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    warnings->push_back("gnuplot failed (see plots/gnuplot.log); pictures may be missing");
    return "";
  }
  *made = true;
  std::string md;
  md += "![convergence](plots/convergence.png)\n\n";
  for (const auto& n : workNames) md += "![work diagram " + n + "](plots/work_" + n + ".png)\n\n";
  md += "![per case](plots/cases.png)\n\n";
  return md;
}

std::string reportMarkdown(const Study& s, const StudyResult& r, double wall, const std::string& pictures,
                           bool gnuplotPresent, bool plotsWanted) {
  const OptimizationResult& o = r.opt;
  const auto names = constraintNames(s);
  const bool maximize = s.objective.kind == ObjectiveKind::MaxEfficiency;
  std::ostringstream m;
  m << "# Design study: " << s.name << "\n\n";
  m << "- study file: `" << s.file << "`\n- scene: `" << s.sceneFile << "`\n";
  m << "- objective: " << objectiveKind(s) << " (aggregate " << aggregateName(s) << ") over cases:";
  for (const auto& c : s.cases) m << " " << c.dropCase.name;
  m << "\n- algorithm: " << s.algorithm.name << (s.algorithm.local.empty() ? "" : " (local " + s.algorithm.local + ")")
    << ", seed " << s.algorithm.seed << ", constraints "
    << (names.empty() ? "none" : describeConstraintHandling(s.algorithm.name, s.algorithm.penalty))
    << "\n";
  m << "- result: **" << o.reason << "** (" << o.nloptName << "), " << o.evaluations << " evaluations ("
    << o.simulations << " simulated), best at evaluation " << o.bestIndex << ", wall time " << shortNum(wall, 4)
    << " s\n";
  m << "- best design " << (o.feasible ? "is feasible" : "is **not feasible**") << "\n\n";
  const double f0 = o.initial.objective, f1 = o.best.objective;
  m << "## Objective\n\n| | baseline | best | change |\n|---|---|---|---|\n";
  m << "| " << (maximize ? "efficiency [-]" : "peak load [N]") << " | " << shortNum(f0) << " | " << shortNum(f1) << " | "
    << (std::isfinite(f0) && std::isfinite(f1) && f0 != 0 ? shortNum(100 * (f1 - f0) / std::abs(f0), 4) + " %" : "-")
    << " |\n\n";
  m << "## Variables\n\n| path | lower | upper | scale | baseline | best |\n|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < s.variables.size(); ++i) {
    const auto& v = s.variables[i];
    m << "| " << v.path << " | " << shortNum(v.lower) << " | " << shortNum(v.upper) << " | " << (v.log ? "log" : "linear")
      << " | " << shortNum(o.x0[i]) << " | " << shortNum(i < o.x.size() ? o.x[i] : NAN) << " |\n";
  }
  if (!names.empty()) {
    m << "\n## Constraints (g <= 0 is feasible)\n\n| constraint | baseline g | best g |\n|---|---|---|\n";
    for (size_t k = 0; k < names.size(); ++k)
      m << "| " << names[k] << " | " << shortNum(k < o.initial.constraints.size() ? o.initial.constraints[k] : NAN)
        << " | " << shortNum(k < o.best.constraints.size() ? o.best.constraints[k] : NAN) << " |\n";
  }
  m << "\n## Cases\n\n| case | peak load [kN] base → best | n_y | stroke [m] | tyre deflection [m] | efficiency | "
       "bottomed |\n|---|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < r.baselineCases.size() && i < r.bestCases.size(); ++i) {
    const auto& a = r.baselineCases[i];
    const auto& b = r.bestCases[i];
    m << "| " << a.name << " | " << shortNum(a.peak_load_N / 1e3, 5) << " → " << shortNum(b.peak_load_N / 1e3, 5) << " | "
      << shortNum(a.load_factor, 4) << " → " << shortNum(b.load_factor, 4) << " | " << shortNum(a.stroke_max_m, 4)
      << " → " << shortNum(b.stroke_max_m, 4) << " | " << shortNum(a.tyre_deflection_max_m, 4) << " → "
      << shortNum(b.tyre_deflection_max_m, 4) << " | " << shortNum(a.efficiency, 4) << " → " << shortNum(b.efficiency, 4)
      << " | " << (a.bottomed ? "yes" : "no") << " → " << (b.bottomed ? "yes" : "no") << " |\n";
  }
  m << "\n## Pictures\n\n";
  if (!plotsWanted) m << "Pictures were not requested; the data and the gnuplot script are in `plots/`.\n";
  else if (!gnuplotPresent) m << "gnuplot was not found, so no pictures were made; the data and the script are in `plots/` (run `gnuplot plots.gp` there).\n";
  else if (pictures.empty()) m << "gnuplot failed (see `plots/gnuplot.log`); the data and the script are in `plots/`.\n";
  else m << pictures;
  m << "\nFiles: `history.csv` (every evaluation), `result.json`, `best.toml` (run it with `simulate`).\n";
  return m.str();
}

}  // namespace

std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string historyHeader(const Study& s) {
  std::string h = "eval";
  for (const auto& v : s.variables) h += "," + v.path;
  h += ",objective";
  for (const auto& n : constraintNames(s)) h += "," + n;
  h += ",feasible,reason";
  return h;
}

std::string historyLine(const EvaluationRecord& r) {
  std::string l = std::to_string(r.index);
  for (double x : r.x) l += "," + num(x);
  const Evaluation& e = r.evaluation;
  l += "," + num(e.ok ? e.objective : NAN);
  for (double g : e.constraints) l += "," + num(e.ok ? g : NAN);
  l += std::string(",") + (r.feasible ? "1" : "0") + ",";
  if (!e.ok) l += csvQuote(e.message.empty() ? "evaluation failed" : e.message);
  return l;
}

EvaluationCache readHistory(const std::string& path, const Study& s, std::string* warning) {
  EvaluationCache cache;
  std::ifstream in(path);
  if (!in) return cache;
  std::string line;
  if (!std::getline(in, line) || line != historyHeader(s)) {
    if (warning) *warning = "'" + path + "' was written for other variables or constraints: not reused";
    return cache;
  }
  const size_t nv = s.variables.size(), nc = constraintNames(s).size();
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const auto f = csvSplit(line);
    if (f.size() != 1 + nv + 1 + nc + 2) continue;  // a torn last line
    std::vector<double> x(nv);
    Evaluation e;
    try {
      for (size_t i = 0; i < nv; ++i) x[i] = std::stod(f[1 + i]);
    } catch (...) {
      continue;
    }
    const std::string& reason = f[1 + nv + 1 + nc + 1];
    e.ok = reason.empty();
    e.message = reason;
    if (e.ok) {
      try {
        e.objective = std::stod(f[1 + nv]);
        for (size_t k = 0; k < nc; ++k) e.constraints.push_back(std::stod(f[2 + nv + k]));
      } catch (...) {
        continue;
      }
    }
    cache.emplace(bitsOf(x), e);
  }
  return cache;
}

std::string bestSceneText(const Study& s, const std::vector<double>& x, const std::string& outDir) {
  toml::table doc = designDocument(s, x);
  // Relative table paths ("*_table" keys) resolve against the scene's directory: rewrite them so that
  // they resolve from outDir.
  for (const char* arr : {"force", "body", "joint", "stop"}) {
    toml::array* a = doc[arr].as_array();
    if (!a) continue;
    for (auto& e : *a) {
      toml::table* t = e.as_table();
      if (!t) continue;
      for (auto& [k, v] : *t) {
        const std::string key(k.str());
        if (key.size() < 6 || key.compare(key.size() - 6, 6, "_table") != 0 || !v.is_string()) continue;
        fs::path p(*v.value<std::string>());
        if (p.is_absolute()) continue;
        std::error_code ec;
        const fs::path abs = fs::absolute(fs::path(s.sceneDir) / p, ec);
        const fs::path rel = fs::relative(abs, fs::absolute(outDir, ec), ec);
        v.as_string()->get() = (ec || rel.empty()) ? abs.lexically_normal().string() : rel.string();
      }
    }
  }
  std::ostringstream o;
  o << "# Best design of study '" << s.name << "' (" << s.file << "), written by optimize from " << s.sceneFile
    << ".\n# Variables:";
  for (size_t i = 0; i < s.variables.size(); ++i) o << " " << s.variables[i].path << " = " << num(x[i]) << ";";
  o << "\n";
  return o.str() + toTomlString(doc);
}

StudyResult runStudy(const Study& s, const RunOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  StudyResult res;
  const fs::path dir(o.outDir);
  fs::create_directories(dir);
  const fs::path histPath = dir / "history.csv";

  EvaluationCache cache;
  if (o.resume) {
    std::string w;
    cache = readHistory(histPath.string(), s, &w);
    if (!w.empty()) res.warnings.push_back(w);
  }
  std::ofstream hist(histPath, std::ios::trunc);
  if (!hist) throw std::runtime_error("cannot write '" + histPath.string() + "'");
  hist << historyHeader(s) << "\n" << std::flush;

  EvaluatorOptions eo;
  eo.threads = o.threads;
  eo.stop = o.stop;
  const Problem p = makeProblem(s, eo);
  AlgorithmSettings a = s.algorithm;
  if (o.maxeval >= 0) a.maxeval = o.maxeval;
  Observer obs;
  obs.stopRequested = o.stop;
  obs.onEvaluation = [&](const EvaluationRecord& r) {
    hist << historyLine(r) << "\n" << std::flush;
    if (o.progress)
      o.progress(r, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  };
  res.opt = runOptimizer(p, a, obs, o.resume ? &cache : nullptr);
  hist.close();

  // Baseline and best, re-simulated: metrics (record = false, as evaluated) and time histories.
  EvaluatorOptions quiet;
  quiet.threads = o.threads;
  const Evaluation e0 = evaluateDesign(s, res.opt.x0, quiet);
  const Evaluation e1 = evaluateDesign(s, res.opt.x, quiet);
  res.baselineCases = e0.cases;
  res.bestCases = e1.cases;
  if (res.opt.best.ok && e1.ok && e1.objective != res.opt.best.objective)
    res.warnings.push_back("re-simulating the best design gave objective " + num(e1.objective) + " instead of " +
                           num(res.opt.best.objective));
  EvaluatorOptions rec = quiet;
  rec.record = true;
  std::vector<CaseResult> baseRuns, bestRuns;
  (void)evaluateDesign(s, res.opt.x0, rec, &baseRuns);
  (void)evaluateDesign(s, res.opt.x, rec, &bestRuns);

  res.bestToml = bestSceneText(s, res.opt.x, dir.string());
  writeFile(dir / "best.toml", res.bestToml);

  const bool gp = o.plots && haveGnuplot();
  bool made = false;
  const std::string pics = makePlots(s, res, baseRuns, bestRuns, dir, gp, &made, &res.warnings);
  res.gnuplot = made;
  if (o.plots && !gp) res.warnings.push_back("gnuplot not found: report.md has no pictures");

  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  writeFile(dir / "result.json", resultJson(s, res, wall));
  writeFile(dir / "report.md", reportMarkdown(s, res, wall, pics, gp, o.plots));
  return res;
}

}  // namespace lg::optim
