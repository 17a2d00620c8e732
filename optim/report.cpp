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

#include "sim/io/compliance.hpp"
#include "sim/io/files.hpp"
#include "sim/core/format.hpp"  // csvField
#include "sim/io/plots.hpp"
#include "sim/io/results.hpp"

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

// Splits one CSV line (quotes as written by csvField, sim/core/format.hpp).
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

std::string objectiveKind(const Study& s) {
  return s.objective.kind == ObjectiveKind::MinPeakLoad ? "min_peak_load" : "max_efficiency";
}
std::string aggregateName(const Study& s) { return s.objective.aggregate == Aggregate::Worst ? "worst" : "weighted_sum"; }

std::string casesOf(const Study& s, CaseRole role) {
  std::string out;
  for (const auto& c : s.cases)
    if (c.role == role) out += (out.empty() ? "" : ", ") + c.dropCase.name;
  return out.empty() ? "none" : out;
}

std::string limitsJson(const CaseVerdict& v) {
  std::ostringstream o;
  o << "[";
  for (size_t i = 0; i < v.limits.size(); ++i) {
    const auto& l = v.limits[i];
    o << (i ? ", " : "") << "{\"metric\": " << jsonString(l.limit.metric) << ", \"value\": " << jsonNumber(l.value)
      << ", \"relation\": " << jsonString(l.limit.upper ? "<=" : ">=") << ", \"limit\": " << jsonNumber(l.limit.bound)
      << ", \"pass\": " << jsonBool(l.pass) << ", \"rule\": " << jsonString(l.limit.rule) << "}";
  }
  o << "]";
  return o.str();
}

std::string casesJson(const Study& s, const std::vector<CaseVerdict>& verdicts, const std::string& in) {
  std::ostringstream j;
  j << "[\n";
  for (size_t i = 0; i < verdicts.size(); ++i) {
    const CaseVerdict& v = verdicts[i];
    const StudyCase& c = s.cases[i];
    j << in << "  {\"name\": " << jsonString(v.name) << ", \"role\": " << jsonString(roleName(c.role))
      << ", \"origin\": " << jsonString(originName(c.origin)) << ", \"within_limits\": " << jsonBool(v.pass)
      << ", \"violations\": [";
    for (size_t k = 0; k < v.reasons.size(); ++k) j << (k ? ", " : "") << jsonString(v.reasons[k]);
    j << "],\n" << in << "   \"limits\": " << limitsJson(v) << ",\n";
    j << in << "   \"metrics\": " << metricsJson(v.metrics, in + "   ") << "}" << (i + 1 < verdicts.size() ? "," : "") << "\n";
  }
  j << in << "]";
  return j.str();
}

std::string resultJson(const Study& s, const StudyResult& r, double wall) {
  const OptimizationResult& o = r.opt;
  std::ostringstream j;
  j << "{\n";
  j << "  \"study\": " << jsonString(s.name) << ",\n";
  j << "  \"study_file\": " << jsonString(s.file) << ",\n";
  j << "  \"scene\": " << jsonString(s.sceneFile) << ",\n";
  j << "  \"algorithm\": {\"name\": " << jsonString(s.algorithm.name) << ", \"local\": " << jsonString(s.algorithm.local)
    << ", \"seed\": " << s.algorithm.seed << ", \"constraints\": "
    << jsonString(s.items.empty() ? "none" : describeConstraintHandling(s.algorithm.name, s.algorithm.penalty)) << "},\n";
  j << "  \"solver\": {\"setting\": " << jsonString(s.solverChoice) << ", \"accuracy_needed\": " << jsonNumber(s.accuracyNeeded)
    << "},\n";
  j << "  \"objective\": {\"kind\": " << jsonString(objectiveKind(s)) << ", \"aggregate\": " << jsonString(aggregateName(s))
    << ", \"cases\": " << jsonString(casesOf(s, CaseRole::Objective)) << ", \"best\": " << jsonNumber(o.best.objective)
    << ", \"baseline\": " << jsonNumber(o.initial.objective) << ", \"scale\": " << jsonNumber(o.objectiveScale) << "},\n";
  j << "  \"feasible\": " << jsonBool(o.feasible) << ",\n";
  j << "  \"certification\": {\"basis\": " << jsonString(s.certification ? s.certification->basisName : "none")
    << ", \"role\": " << jsonString(s.certification ? roleName(s.certificationRole) : "none")
    << ", \"pass\": " << (s.certification ? jsonBool(r.certified) : "null") << "},\n";
  j << "  \"checks_within_limits\": " << jsonBool(r.checksWithinLimits) << ",\n";
  j << "  \"variables\": [\n";
  for (size_t i = 0; i < s.variables.size(); ++i) {
    const Variable& v = s.variables[i];
    j << "    {\"path\": " << jsonString(v.path) << ", \"lower\": " << jsonNumber(v.lower) << ", \"upper\": "
      << jsonNumber(v.upper) << ", \"log\": " << jsonBool(v.log) << ", \"initial\": " << jsonNumber(o.x0[i])
      << ", \"best\": " << jsonNumber(i < o.x.size() ? o.x[i] : NAN) << "}" << (i + 1 < s.variables.size() ? "," : "")
      << "\n";
  }
  j << "  ],\n";
  j << "  \"constraints\": [\n";
  for (size_t k = 0; k < s.items.size(); ++k) {
    const ConstraintItem& it = s.items[k];
    const ConstraintSpec& c = s.constraints[it.spec];
    const double gb = k < o.best.constraints.size() ? o.best.constraints[k] : NAN;
    const double g0 = k < o.initial.constraints.size() ? o.initial.constraints[k] : NAN;
    j << "    {\"name\": " << jsonString(it.name) << ", \"metric\": " << jsonString(c.metric) << ", \"case\": "
      << jsonString(it.caseIndex >= 0 ? s.cases[it.caseIndex].dropCase.name : "") << ", \"relation\": "
      << jsonString(c.upper ? "<=" : ">=") << ", \"bound\": " << jsonNumber(c.bound) << ", \"source\": "
      << jsonString(c.source) << ", \"rule\": " << jsonString(c.rule) << ", \"g_best\": " << jsonNumber(gb)
      << ", \"g_baseline\": " << jsonNumber(g0) << ", \"holds\": " << jsonBool(gb <= 0) << "}"
      << (k + 1 < s.items.size() ? "," : "") << "\n";
  }
  j << "  ],\n";
  j << "  \"interrupted\": " << jsonBool(o.interrupted) << ",\n";
  j << "  \"best_evaluation\": " << o.bestIndex << ",\n";
  j << "  \"evaluations\": " << o.evaluations << ",\n";
  j << "  \"simulated_evaluations\": " << o.simulations << ",\n";
  j << "  \"wall_time_s\": " << jsonNumber(wall) << ",\n";
  j << "  \"nlopt\": {\"code\": " << o.nloptCode << ", \"name\": " << jsonString(o.nloptName)
    << ", \"reason\": " << jsonString(o.reason) << ", \"converged\": " << jsonBool(o.converged) << "},\n";
  if (r.robustness.robust) {
    const Robustness& b = r.robustness;
    j << "  \"robustness\": {\"points\": " << b.points << ", \"robust_objective\": " << jsonNumber(o.best.objective)
      << ", \"nominal_study\": " << jsonBool(b.nominalRun);
    j << ", \"robust_objective_at_nominal\": " << jsonNumber(b.atNominal);
    if (b.nominalRun) {
      const double price = b.atNominal - b.nominalObjective;
      j << ", \"nominal_objective\": " << jsonNumber(b.nominalObjective) << ", \"nominal_feasible\": "
        << jsonBool(b.nominalFeasible) << ", \"nominal_evaluations\": " << b.nominalEvaluations << ", \"price\": "
        << jsonNumber(price) << ", \"price_percent\": " << jsonNumber(100 * price / std::abs(b.nominalObjective))
        << ", \"nominal_optimum_violated_at_corners\": " << b.nominalViolated << ", \"nominal_optimum_worst\": "
        << jsonString(b.nominalWorst) << ", \"nominal_optimum_worst_g\": " << jsonNumber(b.nominalWorstG)
        << ", \"nominal_x\": [";
      for (size_t i = 0; i < b.nominalX.size(); ++i) j << (i ? ", " : "") << jsonNumber(b.nominalX[i]);
      j << "]";
    }
    j << ",\n    \"active\": [";
    for (size_t i = 0; i < b.active.size(); ++i)
      j << (i ? ",\n      " : "\n      ") << "{\"constraint\": " << jsonString(b.active[i].constraint)
        << ", \"case\": " << jsonString(b.active[i].caseName) << ", \"corner\": " << jsonString(b.active[i].corner)
        << ", \"g\": " << jsonNumber(b.active[i].g) << "}";
    j << "]},\n";
  }
  j << "  \"cases\": {\n    \"baseline\": " << casesJson(s, r.baselineVerdicts, "    ") << ",\n";
  j << "    \"best\": " << casesJson(s, r.bestVerdicts, "    ") << "\n  }\n}\n";
  return j.str();
}

// Writes the data files and scripts under DIR/plots; runs gnuplot when present. Returns the markdown
// image lines (or the reason there are none).
std::string makePlots(const Study& s, const StudyResult& r, const std::vector<CaseResult>& base,
                      const std::vector<CaseResult>& best, const fs::path& dir, bool run, bool* made,
                      std::vector<std::string>* warnings) {
  *made = false;
  const fs::path pd = dir / "plots";
  prepareOutputDir(pd.string());
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
    writeFileAtomic((pd / "convergence.dat").string(), d.str());
  }
  // per-case figures
  {
    std::ostringstream d;
    d << "# i case peak_baseline[kN] peak_best[kN] eta_baseline eta_best\n";
    for (size_t i = 0; i < r.baselineCases.size() && i < r.bestCases.size(); ++i)
      d << i << " " << safeFileStem(r.baselineCases[i].name) << " " << num(r.baselineCases[i].peak_load_N / 1e3) << " "
        << num(r.bestCases[i].peak_load_N / 1e3) << " " << num(r.baselineCases[i].efficiency) << " "
        << num(r.bestCases[i].efficiency) << "\n";
    writeFileAtomic((pd / "cases.dat").string(), d.str());
  }
  std::ostringstream gp;
  gp << "set terminal pngcairo size 900,560 noenhanced\n";
  gp << "set grid\nset key top right\n";
  gp << "set output 'convergence.png'\nset title 'Convergence: " << (maximize ? "efficiency" : "peak load [N]")
     << " per evaluation'\nset xlabel 'evaluation'\nset ylabel '" << (maximize ? "objective (efficiency)" : "objective [N]")
     << "'\n";
  gp << "plot 'convergence.dat' using 1:($3==1?$2:1/0) with points pt 7 ps 0.6 lc rgb '#1f77b4' title 'feasible', \\\n"
        "     '' using 1:($3==0?$2:1/0) with points pt 6 ps 0.6 lc rgb '#d62728' title 'infeasible', \\\n"
        "     '' using 1:4 with steps lw 2 lc rgb '#2ca02c' title 'best feasible so far'\n";
  gp << "set output 'cases.png'\nset multiplot layout 1,2 title 'Per case: baseline vs optimum'\n"
        "set style data histograms\nset style histogram clustered gap 1\nset style fill solid 0.8 border -1\n"
        "set autoscale x\nset boxwidth 0.9\nset xtics rotate by -30\nset key top left\nunset xlabel\n"
        "set title 'peak load'\nset ylabel 'P_y,max [kN]'\nset yrange [0:*]\n"
        "plot 'cases.dat' using 3:xtic(2) title 'baseline' lc rgb '#7f7f7f', '' using 4 title 'optimum' lc rgb '#1f77b4'\n"
        "set title 'efficiency'\nset ylabel 'eta [-]'\nset yrange [0:1]\n"
        "plot 'cases.dat' using 5:xtic(2) title 'baseline' lc rgb '#7f7f7f', '' using 6 title 'optimum' lc rgb '#1f77b4'\n"
        "unset multiplot\n";
  writeFileAtomic((pd / "plots.gp").string(), gp.str());
  // One figure per case: the optimum against the baseline, with the case's limits.
  std::vector<std::string> caseStems;
  bool figuresOk = true;
  for (size_t i = 0; i < base.size() && i < best.size() && i < r.bestVerdicts.size(); ++i) {
    const CaseVerdict& v = r.bestVerdicts[i];
    CaseFigure f;
    char title[256];
    std::snprintf(title, sizeof title, "%s: %s (%s), V = %.3f m/s, L = %.3g, W = %.0f kg: optimum %s", s.name.c_str(),
                  v.name.c_str(), roleName(s.cases[i].role), v.metrics.sink_speed_mps, v.metrics.lift_ratio,
                  v.metrics.mass_kg, v.pass ? "within its limits" : "EXCEEDS A LIMIT");
    f.title = title;
    f.run = &best[i];
    f.baseline = &base[i];
    f.runLabel = "optimum, compression";
    f.limits = sceneLimits(s.scene);
    f.drawElementsOf(s.scene);
    if (s.certification) {
      f.limits = compliancePlotLimits(s.scene, *s.certification, v);
      if (s.cases[i].origin != CaseOrigin::Certification) f.limits.loadLimit = f.limits.loadUltimate = NAN;
    }
    const std::string stem = "case_" + safeFileStem(v.name);
    std::string why;
    if (!drawCaseFigure(f, pd.string(), stem, run, &why) && run) {
      figuresOk = false;
      warnings->push_back("picture of case " + v.name + ": " + why);
    }
    caseStems.push_back(stem);
  }
  if (!run) return "";
  const std::string cmd = "cd '" + pd.string() + "' && gnuplot plots.gp > gnuplot.log 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    warnings->push_back("gnuplot failed (see plots/gnuplot.log); pictures may be missing");
    return "";
  }
  *made = figuresOk;
  std::string md;
  md += "![convergence](plots/convergence.png)\n\n![per case](plots/cases.png)\n\n";
  for (size_t i = 0; i < caseStems.size(); ++i)
    md += "![" + r.bestVerdicts[i].name + "](plots/" + caseStems[i] + ".png)\n\n";
  return md;
}

std::string verdictCell(const CaseVerdict& v) {
  if (v.pass) return "within limits";
  std::string s = "**EXCEEDS**: ";
  for (size_t k = 0; k < v.reasons.size(); ++k) s += (k ? "; " : "") + v.reasons[k];
  return s;
}

// The robust study's section: the envelope, the price of robustness, the active corners.
std::string robustnessMarkdown(const Study& s, const StudyResult& r) {
  const Robustness& b = r.robustness;
  const OptimizationResult& o = r.opt;
  std::ostringstream m;
  m << "## Robustness over the servicing and temperature envelope\n\n";
  m << "The steering cases ran at " << b.points << " points of the scene's envelope (the nominal point and "
    << b.points - 1 << " corners); the objective at " << (s.envelope.objectiveWorst ? "its worst point" : "the nominal point")
    << ", every constraint at every point. The envelope:\n\n";
  for (const auto& f : s.scene.envelope.factors()) m << "- " << f << "\n";
  m << "\n";
  if (s.envelope.objectiveWorst)
    m << "The robust optimum's objective is " << shortNum(o.best.objective) << " at its worst point and "
      << shortNum(b.atNominal) << " at the nominal point.\n\n";
  if (b.nominalRun) {
    const double price = b.atNominal - b.nominalObjective;
    m << "**Price of robustness:** the nominal study (the same study at the nominal point only, " << b.nominalEvaluations
      << " evaluations) reaches " << shortNum(b.nominalObjective) << (b.nominalFeasible ? "" : " (not feasible)")
      << "; the robust optimum " << shortNum(b.atNominal) << " at the nominal point: " << (price >= 0 ? "+" : "")
      << shortNum(price) << " (" << (price >= 0 ? "+" : "") << shortNum(100 * price / std::abs(b.nominalObjective), 3)
      << " %).\n\n";
    m << "The nominal optimum breaks " << b.nominalViolated << " of this study's " << s.items.size()
      << " constraints at the points of the envelope";
    if (b.nominalViolated > 0) m << "; the most: `" << b.nominalWorst << "`, g = " << shortNum(b.nominalWorstG) << " (> 0 breaks it)";
    m << ".\n\n";
  }
  m << "Active constraints of the robust optimum (within 1e-3 of their scale):\n\n";
  if (b.active.empty()) m << "none.\n\n";
  else {
    m << "| constraint | case | corner | g |\n|---|---|---|---|\n";
    for (const auto& a : b.active)
      m << "| " << a.constraint << " | " << a.caseName << " | " << a.corner << " | " << shortNum(a.g) << " |\n";
    m << "\n";
  }
  return m.str();
}

std::string reportMarkdown(const Study& s, const StudyResult& r, double wall, const std::string& pictures,
                           bool gnuplotPresent, bool plotsWanted) {
  const OptimizationResult& o = r.opt;
  const bool maximize = s.objective.kind == ObjectiveKind::MaxEfficiency;
  std::ostringstream m;
  m << "# Design study: " << s.name << "\n\n";
  m << "- study file: `" << s.file << "`\n- scene: `" << s.sceneFile << "`\n";
  m << "- objective: " << objectiveKind(s) << " (aggregate " << aggregateName(s) << ") over the objective cases: "
    << casesOf(s, CaseRole::Objective) << "\n";
  m << "- constraint cases: " << casesOf(s, CaseRole::Constraint) << "; check cases (reported, never steer): "
    << casesOf(s, CaseRole::Check) << "\n";
  if (s.certification)
    m << "- certification matrix: `" << s.certification->basisName << "`, its cases "
      << (s.certificationRole == CaseRole::Check ? "reported as checks" : "constrain the design with its limits") << "\n";
  m << "- algorithm: " << s.algorithm.name << (s.algorithm.local.empty() ? "" : " (local " + s.algorithm.local + ")")
    << ", seed " << s.algorithm.seed << ", constraints "
    << (s.items.empty() ? "none" : describeConstraintHandling(s.algorithm.name, s.algorithm.penalty)) << "\n";
  m << "- drop-test solver: " << s.solverChoice << "\n";
  m << "- result: **" << o.reason << "** (" << o.nloptName << "), " << o.evaluations << " evaluations ("
    << o.simulations << " simulated), best at evaluation " << o.bestIndex << ", wall time " << shortNum(wall, 4)
    << " s\n";
  m << "- best design " << (o.feasible ? "is feasible (every constraint holds)" : "is **not feasible**");
  if (s.certification) m << "; certification matrix: " << (r.certified ? "**PASS**" : "**FAIL**");
  m << "; check cases: " << (r.checksWithinLimits ? "within their limits" : "**some exceed a limit** (see Cases)") << "\n\n";
  if (r.robustness.robust) m << robustnessMarkdown(s, r);
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
  if (!s.items.empty()) {
    m << "\n## Constraints (g <= 0 holds)\n\n| constraint | case | bound | source | baseline g | best g |\n"
         "|---|---|---|---|---|---|\n";
    for (size_t k = 0; k < s.items.size(); ++k) {
      const ConstraintItem& it = s.items[k];
      const ConstraintSpec& c = s.constraints[it.spec];
      const double gb = k < o.best.constraints.size() ? o.best.constraints[k] : NAN;
      const double g0 = k < o.initial.constraints.size() ? o.initial.constraints[k] : NAN;
      m << "| " << c.metric << " | " << (it.caseIndex >= 0 ? s.cases[it.caseIndex].dropCase.name : "design") << " | "
        << (c.upper ? "<= " : ">= ") << shortNum(c.bound) << " (" << c.rule << ") | " << c.source << " | "
        << shortNum(g0) << (g0 > 0 ? " ✗" : "") << " | " << shortNum(gb) << (gb > 0 ? " **✗**" : "") << " |\n";
    }
  }
  m << "\n## Cases: every case of the study, its scene and its matrix (baseline → best)\n\n"
       "| case | role | V [m/s] | L | W [kg] | peak load [kN] | n_g | stroke [m] (margin) | tyre [m] (margin) | "
       "efficiency | best design |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < r.baselineCases.size() && i < r.bestCases.size() && i < r.bestVerdicts.size(); ++i) {
    const auto& a = r.baselineCases[i];
    const auto& b = r.bestCases[i];
    m << "| " << b.name << " | " << roleName(s.cases[i].role) << " | " << shortNum(b.sink_speed_mps, 4) << " | "
      << shortNum(b.lift_ratio, 3) << " | " << shortNum(b.mass_kg, 6) << " | " << shortNum(a.peak_load_N / 1e3, 5)
      << " → " << shortNum(b.peak_load_N / 1e3, 5) << " | " << shortNum(a.load_factor, 4) << " → "
      << shortNum(b.load_factor, 4) << " | " << shortNum(a.stroke_max_m, 4) << " → " << shortNum(b.stroke_max_m, 4) << " ("
      << shortNum(b.stroke_margin_m, 3) << ") | " << shortNum(a.tyre_deflection_max_m, 4) << " → "
      << shortNum(b.tyre_deflection_max_m, 4) << " (" << shortNum(b.tyre_margin_m, 3) << ") | "
      << shortNum(a.efficiency, 4) << " → " << shortNum(b.efficiency, 4) << " | " << verdictCell(r.bestVerdicts[i]) << " |\n";
  }
  m << "\nLimits: matrix cases are held to the rules' limits (load factor, stroke margin, tyre); every other case to "
       "the stroke and tyre limits and the study's constraints that name it. A check case that exceeds a limit is "
       "shown here and does not make the design infeasible: only the constraint cases do.\n";
  m << "\n## Pictures\n\n";
  if (!plotsWanted) m << "Pictures were not requested; the data and the gnuplot scripts are in `plots/`.\n";
  else if (!gnuplotPresent) m << "gnuplot was not found, so no pictures were made; the data and the scripts are in `plots/` (run `gnuplot plots.gp` there).\n";
  else if (pictures.empty()) m << "gnuplot failed (see `plots/gnuplot.log`); the data and the scripts are in `plots/`.\n";
  else m << pictures;
  m << "\nFiles: `history.csv` (every evaluation), `result.json`, `best.toml` (run it with `simulate` or `certify`).\n";
  return m.str();
}

}  // namespace

std::vector<Limit> reportLimits(const Study& s, int caseIndex) {
  const StudyCase& c = s.cases[caseIndex];
  std::vector<Limit> out;
  const CertCase* cc = c.origin == CaseOrigin::Certification && s.certification ? s.certification->findCase(c.baseName)
                                                                                : nullptr;
  out = cc ? caseLimits(*s.certification, *cc, s.scene) : checkLimits(s.certification.get(), s.scene);
  for (const auto& spec : s.constraints)
    if (spec.source == "study" && std::find(spec.cases.begin(), spec.cases.end(), caseIndex) != spec.cases.end())
      out.push_back({spec.metric, spec.upper, spec.bound, spec.rule});
  return out;
}

std::string historyHeader(const Study& s) {
  std::string h = "eval";
  for (const auto& v : s.variables) h += "," + v.path;
  h += ",objective";
  for (const auto& n : constraintNames(s)) h += "," + n;
  h += ",feasible,reason";
  return h;
}

std::string historyLine(const Study& s, const EvaluationRecord& r) {
  std::string l = std::to_string(r.index);
  for (double x : r.x) l += "," + num(x);
  const Evaluation& e = r.evaluation;
  l += "," + num(e.ok ? e.objective : NAN);
  for (size_t k = 0; k < s.items.size(); ++k)  // every row has every field: a failed one too
    l += "," + num(e.ok && k < e.constraints.size() ? e.constraints[k] : NAN);
  l += std::string(",") + (r.feasible ? "1" : "0") + ",";
  if (!e.ok) l += csvField(e.message.empty() ? "evaluation failed" : e.message);
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
  relocateTablePaths(doc, s.sceneDir, outDir);  // relative tables resolve from outDir
  std::ostringstream o;
  o << "# Best design of study '" << s.name << "' (" << s.file << "), written by optimize from " << s.sceneFile
    << ".\n# Variables:";
  for (size_t i = 0; i < s.variables.size(); ++i) o << " " << s.variables[i].path << " = " << num(x[i]) << ";";
  o << "\n";
  return o.str() + writtenSceneText(s.scene.text, s.sceneFile, doc);
}

namespace {

// The optimiser's run with every evaluation logged to history.csv as it finishes (a line that cannot be
// written stops the study); with o.resume the designs already in the log are not simulated again.
void optimiseLogged(const Study& s, const RunOptions& o, const fs::path& histPath,
                    std::chrono::steady_clock::time_point t0, StudyResult& res) {
  EvaluationCache cache;
  if (o.resume) {
    std::string w;
    cache = readHistory(histPath.string(), s, &w);
    if (!w.empty()) res.warnings.push_back(w);
  }
  LineLog hist;
  if (!hist.open(histPath.string()) || !hist.write(historyHeader(s))) throw std::runtime_error(hist.error());

  EvaluatorOptions eo;
  eo.threads = o.threads;
  eo.stop = o.stop;
  const Problem p = makeProblem(s, eo);
  AlgorithmSettings a = s.algorithm;
  if (o.maxeval >= 0) a.maxeval = o.maxeval;
  Observer obs;
  // A history line that cannot be written stops the study: it must not run on without its log.
  obs.stopRequested = [&] { return !hist.error().empty() || (o.stop && o.stop()); };
  obs.onEvaluation = [&](const EvaluationRecord& r) {
    hist.write(historyLine(s, r));
    if (o.progress)
      o.progress(r, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  };
  res.opt = runOptimizer(p, a, obs, o.resume ? &cache : nullptr);
  if (!hist.close()) throw std::runtime_error(hist.error() + " (the study stopped there)");
}

// The baseline and the best design re-simulated on every case of the study (steering cases and checks)
// with their time histories, into res's case metrics; a design the scene rejects runs no case, and each
// case then fails with the design's reason.
void recheckCases(const Study& s, const RunOptions& o, StudyResult& res, std::vector<CaseResult>& baseRuns,
                  std::vector<CaseResult>& bestRuns) {
  EvaluatorOptions all;
  all.threads = o.threads;
  all.record = true;
  all.checks = true;
  const Evaluation e0 = evaluateDesign(s, res.opt.x0, all, &baseRuns);
  const Evaluation e1 = evaluateDesign(s, res.opt.x, all, &bestRuns);
  for (auto* runs : {&baseRuns, &bestRuns}) {
    const Evaluation& e = runs == &baseRuns ? e0 : e1;
    if (runs->size() == s.cases.size()) continue;
    runs->assign(s.cases.size(), CaseResult{});
    for (size_t i = 0; i < s.cases.size(); ++i) {
      (*runs)[i].metrics.name = s.cases[i].dropCase.name;
      (*runs)[i].metrics.ok = false;
      (*runs)[i].metrics.message = e.message;
    }
  }
  for (const auto& r : baseRuns) res.baselineCases.push_back(r.metrics);
  for (const auto& r : bestRuns) res.bestCases.push_back(r.metrics);
  // (a gradient study's values are the Jet run's: the double run's to round-off, not bit for bit)
  if (res.opt.best.ok && e1.ok &&
      std::abs(e1.objective - res.opt.best.objective) > (res.opt.best.hasGradient ? 1e-9 * std::abs(e1.objective) : 0.0))
    res.warnings.push_back("re-simulating the best design gave objective " + num(e1.objective) + " instead of " +
                           num(res.opt.best.objective));
}

// Each case of the baseline and the best design judged against its limits; the best design's
// certification verdict and a warning for every limit it exceeds.
void judgeCases(const Study& s, StudyResult& res) {
  res.certified = s.certification != nullptr;
  for (size_t i = 0; i < s.cases.size() && i < res.bestCases.size(); ++i) {
    const std::vector<Limit> limits = reportLimits(s, static_cast<int>(i));
    auto verdict = [&](const CaseMetrics& m) {
      CertCase cc;
      cc.name = m.name;
      cc.sinkSpeed = m.sink_speed_mps;
      cc.liftRatio = m.lift_ratio;
      cc.mass = m.mass_kg;
      cc.duration = s.cases[i].dropCase.duration;
      if (s.cases[i].origin == CaseOrigin::Certification)
        if (const CertCase* c = s.certification->findCase(s.cases[i].baseName)) cc = *c;
      return assessCase(roleName(s.cases[i].role), cc, m, limits);
    };
    res.baselineVerdicts.push_back(verdict(res.baselineCases[i]));
    res.bestVerdicts.push_back(verdict(res.bestCases[i]));
    const CaseVerdict& v = res.bestVerdicts.back();
    if (s.cases[i].origin == CaseOrigin::Certification) res.certified = res.certified && v.pass;
    if (!v.pass) {
      if (!s.cases[i].steers()) res.checksWithinLimits = false;
      std::string why;
      for (size_t k = 0; k < v.reasons.size(); ++k) why += (k ? "; " : "") + v.reasons[k];
      // A case over the envelope: one warning with its count of points (report.md lists each).
      const std::string& base = s.cases[i].baseName;
      int failing = 0, points = 0;
      size_t first = i;
      for (size_t j = 0; j < s.cases.size() && j < res.bestCases.size(); ++j)
        if (s.cases[j].baseName == base && s.cases[j].steers() == s.cases[i].steers() && !s.cases[j].corner.empty()) {
          ++points;
          if (j < i && j < res.bestVerdicts.size() && !res.bestVerdicts[j].pass) first = std::min(first, j);
        }
      if (first < i) continue;  // (said with the first failing point)
      for (size_t j = 0; j < s.cases.size() && j < res.bestCases.size(); ++j)
        if (s.cases[j].baseName == base && s.cases[j].steers() == s.cases[i].steers() && !s.cases[j].corner.empty()) {
          const std::vector<Limit> lj = reportLimits(s, static_cast<int>(j));
          failing += assessCase(roleName(s.cases[j].role), CertCase{}, res.bestCases[j], lj).pass ? 0 : 1;
        }
      res.warnings.push_back("the best design exceeds a limit in " + std::string(roleName(s.cases[i].role)) + " case '" +
                             (points > 0 ? base + "' at " + std::to_string(failing) + " of " + std::to_string(points) +
                                               " points of the envelope (first: " + v.name + ")"
                                         : v.name + "'") +
                             ": " + why);
    }
  }
  if (s.certification)
    for (const auto& u : unitItems(*s.certification)) res.certified = res.certified && u.pass;
}

// A robust study's active corners and, with nominal_study, its nominal variant run (logged to
// DIR/nominal/history.csv) and its optimum checked against the robust study's constraints.
void measureRobustness(const Study& s, const RunOptions& o, const fs::path& dir,
                       std::chrono::steady_clock::time_point t0, StudyResult& res) {
  Robustness& b = res.robustness;
  b.robust = true;
  b.points = static_cast<int>(s.corners.size());
  const std::vector<double> scales = constraintScales(s);
  const Evaluation& best = res.opt.best;
  for (size_t k = 0; k < s.items.size() && k < best.constraints.size(); ++k)
    if (best.constraints[k] > -1e-3 * scales[k]) {
      const ConstraintItem& it = s.items[k];
      const StudyCase* c = it.caseIndex >= 0 ? &s.cases[it.caseIndex] : nullptr;
      b.active.push_back({it.name, c ? c->baseName : "design", c ? c->corner : "", best.constraints[k]});
    }
  // The robust optimum's objective at the nominal point: its objective cases there, reduced as the study's.
  const bool peak = s.objective.kind == ObjectiveKind::MinPeakLoad;
  for (size_t i = 0; i < s.cases.size() && i < res.bestCases.size(); ++i) {
    if (s.cases[i].baseRole != CaseRole::Objective || !(s.cases[i].corner.empty() || s.cases[i].corner == "nominal")) continue;
    const double f = peak ? res.bestCases[i].peak_load_N : res.bestCases[i].efficiency;
    if (s.objective.aggregate == Aggregate::WeightedSum) b.atNominal = (std::isnan(b.atNominal) ? 0.0 : b.atNominal) + s.cases[i].weight * f;
    else b.atNominal = std::isnan(b.atNominal) ? f : peak ? std::max(b.atNominal, f) : std::min(b.atNominal, f);
  }
  if (!s.envelope.nominalStudy || (o.stop && o.stop())) return;
  const Study nominal = loadStudy(s.file, s.sets, true);
  const fs::path nd = dir / "nominal";
  prepareOutputDir(nd.string());
  StudyResult nr;
  RunOptions no = o;
  no.resume = false;
  no.progress = nullptr;
  optimiseLogged(nominal, no, nd / "history.csv", t0, nr);
  if (nr.opt.history.empty()) return;
  b.nominalRun = true;
  b.nominalObjective = nr.opt.best.objective;
  b.nominalFeasible = nr.opt.feasible;
  b.nominalX = nr.opt.x;
  b.nominalEvaluations = nr.opt.evaluations;
  EvaluatorOptions eo;
  eo.threads = o.threads;
  eo.stop = o.stop;
  const Evaluation e = evaluateDesign(s, nr.opt.x, eo);
  double worst = -std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < e.constraints.size() && k < s.items.size(); ++k) {
    if (e.constraints[k] > 0) ++b.nominalViolated;
    if (e.constraints[k] > 0 && e.constraints[k] / scales[k] > worst) {
      worst = e.constraints[k] / scales[k];
      b.nominalWorst = s.items[k].name;
      b.nominalWorstG = e.constraints[k];
    }
  }
}

}  // namespace

// A study: the optimiser's run, logged; then the baseline and the best design re-checked on every case,
// judged, and written (best.toml, plots, result.json, report.md).
StudyResult runStudy(const Study& s, const RunOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  StudyResult res;
  const fs::path dir(o.outDir);
  prepareOutputDir(dir.string());
  optimiseLogged(s, o, dir / "history.csv", t0, res);
  if (res.opt.history.empty()) {  // interrupted before the baseline finished: no design to report
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    writeFileAtomic((dir / "result.json").string(),
                    "{\n  \"study\": " + jsonString(s.name) + ",\n  \"feasible\": false,\n  \"evaluations\": 0,\n"
                    "  \"interrupted\": true,\n  \"nlopt\": {\"reason\": " + jsonString(res.opt.reason) +
                    "},\n  \"wall_time_s\": " + jsonNumber(wall) + "\n}\n");
    writeFileAtomic((dir / "report.md").string(), "# Design study: " + s.name + "\n\n" + res.opt.reason + ".\n");
    return res;
  }
  std::vector<CaseResult> baseRuns, bestRuns;
  recheckCases(s, o, res, baseRuns, bestRuns);
  judgeCases(s, res);
  if (s.envelope.robust()) measureRobustness(s, o, dir, t0, res);

  res.bestToml = bestSceneText(s, res.opt.x, dir.string());
  writeFileAtomic((dir / "best.toml").string(), stampToml(res.bestToml, o.provenance));

  const bool gp = o.plots && haveGnuplot();
  bool made = false;
  const std::string pics = makePlots(s, res, baseRuns, bestRuns, dir, gp, &made, &res.warnings);
  res.gnuplot = made;
  if (o.plots && !gp) res.warnings.push_back("gnuplot not found: report.md has no pictures");

  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  writeFileAtomic((dir / "result.json").string(), stampJson(resultJson(s, res, wall), o.provenance));
  writeFileAtomic((dir / "report.md").string(), stampMarkdown(reportMarkdown(s, res, wall, pics, gp, o.plots), o.provenance));
  return res;
}

}  // namespace lg::optim
