// Calibration outputs: result.json, report.md, the histories, calibrated.toml, the pictures (report.hpp).
#include "calib/report.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "sim/core/format.hpp"
#include "sim/io/files.hpp"
#include "sim/io/json.hpp"
#include "sim/io/overrides.hpp"
#include "sim/io/plots.hpp"  // haveGnuplot

namespace fs = std::filesystem;

namespace lg::calib {

namespace {

// A gnuplot single-quoted string.
std::string gpString(const std::string& s) {
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("''") : std::string(1, ch);
  return q + "'";
}

std::string interval(double lo, double hi) {
  if (!std::isfinite(lo)) return "-";
  return "[" + shortNumber(lo, 5) + ", " + shortNumber(hi, 5) + "]";
}

std::string caseJson(const DropCase& d) {
  std::ostringstream j;
  j << "{\"name\": " << jsonString(d.name) << ", \"sink_speed_mps\": " << jsonNumber(d.sinkSpeed) << ", \"lift_ratio\": "
    << jsonNumber(d.liftRatio) << ", \"duration_s\": " << jsonNumber(d.duration) << ", \"masses_kg\": {";
  bool first = true;
  for (const auto& [body, mass] : d.masses) {
    j << (first ? "" : ", ") << jsonString(body) << ": " << jsonNumber(mass);
    first = false;
  }
  return j.str() + "}}";
}

std::string statsJson(const ChannelStats& s) {
  return "{\"mean\": " + jsonNumber(s.mean) + ", \"rms\": " + jsonNumber(s.rms) + ", \"max_abs\": " + jsonNumber(s.maxAbs) +
         ", \"t_max_abs_s\": " + jsonNumber(s.tMaxAbs) + ", \"lag1_autocorrelation\": " + jsonNumber(s.lag1) + "}";
}

std::string matrixJson(const Eigen::MatrixXd& M) {
  std::string j = "[";
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    j += i ? ",\n    [" : "\n    [";
    for (Eigen::Index k = 0; k < M.cols(); ++k) j += (k ? ", " : "") + jsonNumber(M(i, k));
    j += "]";
  }
  return j + "]";
}

// "fitted, converged after 9 iterations" and the like.
std::string outcome(const FitResult& r) {
  if (!r.ident.identifiable) return "NOT IDENTIFIABLE";
  return r.converged ? "converged" : "stopped before converging";
}

std::string covarianceSource(const Calibration& c) {
  return std::string("ceres::Covariance (dense SVD) of the weighted residuals' Jacobian at the optimum, scaled by the "
                     "residual variance estimated from the fit, ") +
         (c.fit.loss == Loss::None ? "s^2 = sum(r^2) / (m - n)" : "s^2 = (1.4826 median |r|)^2 (robust loss)");
}

// The unknown's kind for the tables: the parameters, then one t_shift per measurement that fits it.
bool isShift(const Calibration& c, std::size_t i) { return i >= c.parameters.size(); }

}  // namespace

std::string parameterTable(const FitResult& r) {
  std::ostringstream o;
  char b[400];
  std::snprintf(b, sizeof b, "  %-24s %-6s %13s %13s %11s  %s\n", "unknown", "unit", "initial", "fitted", "std. dev.",
                (shortNumber(100 * 0.95, 3) + " % interval").c_str());
  o << b;
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    std::snprintf(b, sizeof b, "  %-24s %-6s %13s %13s %11s  %s%s\n", r.names[i].c_str(), r.units[i].c_str(),
                  shortNumber(r.initial[i]).c_str(), shortNumber(r.value[i], 8).c_str(), shortNumber(r.sd[i], 3).c_str(),
                  interval(r.lo[i], r.hi[i]).c_str(), r.atBound[i] ? "  (at a bound)" : "");
    o << b;
  }
  return o.str();
}

std::string resultJson(const Calibration& c, const FitResult& r) {
  std::ostringstream j;
  j << "{\n  \"calibration\": " << jsonString(c.name) << ",\n  \"calibration_file\": " << jsonString(c.file)
    << ",\n  \"scene\": " << jsonString(c.sceneFile) << ",\n  \"outcome\": " << jsonString(outcome(r))
    << ",\n  \"jacobian\": " << jsonString(r.jacobianSource) << ",\n  \"covariance\": " << jsonString(covarianceSource(c))
    << ",\n  \"residual_variance_from_fit\": true,\n  \"s2\": " << jsonNumber(r.s2) << ",\n  \"residuals\": " << r.residuals
    << ",\n  \"unknowns\": " << r.unknowns << ",\n  \"dof\": " << r.dof << ",\n  \"confidence\": "
    << jsonNumber(c.fit.confidence) << ",\n  \"t_quantile\": " << jsonNumber(r.t) << ",\n  \"loss\": {\"kind\": "
    << jsonString(lossName(c.fit.loss)) << ", \"scale\": " << jsonNumber(c.fit.lossScale) << "},\n  \"ceres\": {\"termination\": "
    << jsonString(r.termination) << ", \"message\": " << jsonString(r.ceresMessage) << ", \"converged\": "
    << jsonBool(r.converged) << ", \"iterations\": " << r.iterations << ", \"initial_cost\": " << jsonNumber(r.initialCost)
    << ", \"final_cost\": " << jsonNumber(r.finalCost) << ", \"evaluations\": " << r.evaluations << "},\n";
  j << "  \"identifiability\": {\"identifiable\": " << jsonBool(r.ident.identifiable) << ", \"rcond\": "
    << jsonNumber(r.ident.rcond) << ", \"threshold\": " << jsonNumber(r.ident.threshold) << ", \"limit\": "
    << jsonNumber(r.ident.limit) << ", \"column_errors\": [";
  for (std::size_t k = 0; k < r.ident.columnError.size(); ++k) j << (k ? ", " : "") << jsonNumber(r.ident.columnError[k]);
  j << "], \"involved\": [";
  for (std::size_t k = 0; k < r.ident.involved.size(); ++k) j << (k ? ", " : "") << jsonString(r.names[r.ident.involved[k]]);
  j << "], \"message\": " << jsonString(r.ident.message) << "},\n  \"parameters\": [\n";
  for (std::size_t i = 0; i < r.names.size(); ++i)
    j << "    {\"name\": " << jsonString(r.names[i]) << ", \"kind\": " << jsonString(isShift(c, i) ? "t_shift" : "parameter")
      << ", \"unit\": " << jsonString(r.units[i]) << ", \"lower\": " << jsonNumber(r.lower[i]) << ", \"upper\": "
      << jsonNumber(r.upper[i]) << ", \"initial\": " << jsonNumber(r.initial[i]) << ", \"value\": " << jsonNumber(r.value[i])
      << ", \"sd\": " << jsonNumber(r.sd[i]) << ", \"interval\": [" << jsonNumber(r.lo[i]) << ", " << jsonNumber(r.hi[i])
      << "], \"at_bound\": " << jsonBool(r.atBound[i]) << "}" << (i + 1 < r.names.size() ? "," : "") << "\n";
  j << "  ],\n  \"covariance_computed\": " << jsonBool(r.covariance) << ",\n  \"covariance_message\": "
    << jsonString(r.covarianceMessage) << ",\n  \"correlation\": " << (r.covariance ? matrixJson(r.corr) : "null")
    << ",\n  \"covariance_matrix\": " << (r.covariance ? matrixJson(r.cov) : "null") << ",\n  \"measurements\": [\n";
  for (std::size_t m = 0; m < c.measurements.size(); ++m) {
    const Measurement& me = c.measurements[m];
    const MeasurementFit& f = r.measurements[m];
    j << "    {\"name\": " << jsonString(me.name) << ", \"file\": " << jsonString(me.file) << ", \"case\": " << caseJson(me.dropCase)
      << ", \"samples\": " << me.t.size() << ", \"t_first_s\": " << jsonNumber(me.t.front()) << ", \"t_last_s\": "
      << jsonNumber(me.t.back()) << ", \"t_shift\": {\"fitted\": " << jsonBool(me.shift.fit) << ", \"value\": "
      << jsonNumber(r.fitted.shift[m]) << "}, \"channels\": [";
    for (std::size_t k = 0; k < me.channels.size(); ++k) {
      const Channel& ch = me.channels[k];
      j << (k ? ",\n      " : "\n      ") << "{\"name\": " << jsonString(ch.name) << ", \"unit\": " << jsonString(ch.unit)
        << ", \"csv_column\": " << jsonString(ch.csvColumn) << ", \"fitted\": " << jsonBool(ch.fitted()) << ", \"weight\": "
        << jsonNumber(ch.weight) << ", \"sigma\": " << jsonNumber(ch.sigma) << ", \"before\": " << statsJson(f.statsBefore[k])
        << ", \"after\": " << statsJson(f.statsAfter[k]) << "}";
    }
    j << "]}" << (m + 1 < c.measurements.size() ? "," : "") << "\n";
  }
  j << "  ],\n  \"warnings\": [";
  for (std::size_t k = 0; k < r.warnings.size(); ++k) j << (k ? ", " : "") << jsonString(r.warnings[k]);
  return j.str() + "]\n}\n";
}

std::string historiesCsv(const Calibration& c, const FitResult& r, std::size_t m) {
  const Measurement& me = c.measurements[m];
  const MeasurementFit& f = r.measurements[m];
  std::ostringstream o;
  o << "t[s],t_sim[s]";
  for (const Channel& ch : me.channels) {
    const std::string u = "[" + ch.unit + "]";
    o << "," << ch.name << "_measured" << u << "," << ch.name << "_initial" << u << "," << ch.name << "_fitted" << u << ","
      << ch.name << "_residual" << u;
  }
  o << "\n";
  for (std::size_t i = 0; i < me.t.size(); ++i) {
    o << exactNumber(me.t[i]) << "," << exactNumber(me.t[i] - r.fitted.shift[m]);
    for (std::size_t k = 0; k < me.channels.size(); ++k) {
      const double b = f.before.ok ? f.before.y[k][i] : NAN, a = f.after.ok ? f.after.y[k][i] : NAN;
      o << "," << exactNumber(me.y[k][i]) << "," << exactNumber(b) << "," << exactNumber(a) << "," << exactNumber(a - me.y[k][i]);
    }
    o << "\n";
  }
  return o.str();
}

std::string calibratedToml(const Calibration& c, const FitResult& r, const std::string& outDir) {
  toml::table doc = c.scene.doc;
  std::vector<std::string> paths;
  for (const auto& q : c.parameters) paths.push_back(q.path);
  inlineTables(doc, c.scene, paths);
  for (std::size_t i = 0; i < c.parameters.size(); ++i) setParameter(doc, c.parameters[i].path, r.fitted.x[i], c.file);
  relocateTablePaths(doc, c.sceneDir, outDir);
  // The inline drops of the measurements as cases, so that `simulate calibrated.toml --case <measurement>`
  // runs each measured drop.
  std::vector<std::string> added;
  for (const Measurement& m : c.measurements) {
    if (m.sceneCase >= 0) continue;
    bool taken = false;
    for (const auto& sc : c.scene.cases) taken = taken || sc.name == m.dropCase.name;
    for (const auto& a : added) taken = taken || a == m.dropCase.name;
    if (taken) continue;
    toml::table t{{"name", m.dropCase.name}, {"sink_speed", m.dropCase.sinkSpeed}, {"lift_ratio", m.dropCase.liftRatio},
                  {"duration", m.dropCase.duration}};
    if (!m.dropCase.masses.empty()) {
      toml::table masses;
      for (const auto& [body, mass] : m.dropCase.masses) masses.insert(body, mass);
      t.insert("masses", masses);
    }
    if (!doc.contains("case")) doc.insert("case", toml::array{});
    doc["case"].as_array()->push_back(t);
    added.push_back(m.dropCase.name);
  }
  std::ostringstream o;
  o << "# The scene " << c.sceneFile << " calibrated by calibrate from " << c.file << " (" << outcome(r) << ").\n# Fitted:";
  for (std::size_t i = 0; i < c.parameters.size(); ++i)
    o << " " << c.parameters[i].path << " = " << exactNumber(r.fitted.x[i]) << " +- " << shortNumber(r.sd[i], 3) << " "
      << c.parameters[i].unit << ";";
  o << "\n";
  if (!added.empty()) {
    o << "# Cases added for the measured drops:";
    for (const auto& a : added) o << " " << a;
    o << "\n";
  }
  return o.str() + writtenSceneText(c.scene.text, c.sceneFile, doc);
}

namespace {

std::string measurementsSection(const Calibration& c, const FitResult& r) {
  std::ostringstream m;
  m << "## Measurements\n\n| measurement | file | drop | samples | t [s] | t_shift [s] | channels (CSV column; weight or sigma) |\n"
       "|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < c.measurements.size(); ++k) {
    const Measurement& me = c.measurements[k];
    const DropCase& d = me.dropCase;
    m << "| " << me.name << " | `" << me.file << "` | " << d.name << ": V = " << shortNumber(d.sinkSpeed) << " m/s, L = "
      << shortNumber(d.liftRatio) << ", " << shortNumber(d.duration) << " s | " << me.t.size() << " | "
      << shortNumber(me.t.front()) << " .. " << shortNumber(me.t.back()) << " | "
      << (me.shift.fit ? "fitted in [" + shortNumber(me.shift.lower) + ", " + shortNumber(me.shift.upper) + "]: " +
                             shortNumber(r.fitted.shift[k], 6)
                       : shortNumber(me.shift.value) + " (known)")
      << " |";
    for (const Channel& ch : me.channels)
      m << " " << ch.name << " [" << ch.unit << "] (" << ch.csvColumn << "; "
        << (std::isfinite(ch.sigma) ? "sigma " + shortNumber(ch.sigma) + " " + ch.unit
                                    : ch.fitted() ? "weight " + shortNumber(ch.weight) + " 1/" + ch.unit : "compared, not fitted")
        << ")";
    m << " |\n";
  }
  return m.str() + "\n";
}

std::string parametersSection(const Calibration& c, const FitResult& r) {
  std::ostringstream m;
  m << "## Fitted values\n\n";
  if (!r.ident.identifiable) m << "**" << r.ident.message << "**\n\n";
  m << "| unknown | unit | bounds | initial | fitted | std. dev. | " << shortNumber(100 * c.fit.confidence, 3)
    << " % interval | std. dev. / value |\n|---|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < r.names.size(); ++i)
    m << "| " << r.names[i] << " | " << r.units[i] << " | [" << shortNumber(r.lower[i]) << ", " << shortNumber(r.upper[i])
      << "] | " << shortNumber(r.initial[i]) << " | **" << shortNumber(r.value[i], 8) << "**" << (r.atBound[i] ? " (at a bound)" : "")
      << " | " << shortNumber(r.sd[i], 3) << " | " << interval(r.lo[i], r.hi[i]) << " | "
      << (isShift(c, i) || r.value[i] == 0 ? "-" : shortNumber(r.sd[i] / std::abs(r.value[i]), 3)) << " |\n";
  double worst = 0;
  for (double e : r.ident.columnError) worst = std::max(worst, e);
  m << "\nIdentifiability: the weighted Jacobian with its columns scaled to unit length has a smallest singular value "
    << shortNumber(r.ident.rcond, 3) << " of its largest; the limit in that direction is " << shortNumber(r.ident.limit, 3)
    << ", the larger of the threshold " << shortNumber(r.ident.threshold, 3) << " and 10 times what the columns' own errors "
    << "could give it (estimated from a second Jacobian with twice the steps; the largest column error "
    << shortNumber(worst, 3) << " of the column).\n";
  m << "\nJacobian: **" << r.jacobianSource << "**. Covariance: " << covarianceSource(c) << " = " << shortNumber(r.s2, 5) << " (m = "
    << r.residuals << " fitted samples, n = " << r.unknowns << " unknowns, " << r.dof << " degrees of freedom); the "
    << "interval is value +- t sd with Student's t = " << shortNumber(r.t, 5) << ". The residual variance is estimated from "
    << "the fit, so the standard deviations hold whatever the weights' scale; with sigma given per channel, s^2 near 1 says "
    << "the stated noise matches the residuals. The uncertainties are statistical only: they assume independent noise "
       "of constant variance and exclude the model's form error and the residuals' autocorrelation (the lag-1 "
       "autocorrelation of each channel's residuals is in the table below; near 1 the intervals are too narrow).";
  if (c.fit.loss != Loss::None)
    m << " With the robust loss (" << lossName(c.fit.loss) << ", scale " << shortNumber(c.fit.lossScale)
      << ") Ceres's covariance uses the loss-corrected Jacobian, and s^2 is estimated robustly, s = 1.4826 median |r| "
         "(outliers do not inflate it).";
  m << "\n\n";
  if (r.covariance) {
    m << "### Correlation matrix\n\n| |";
    for (const auto& n : r.names) m << " " << n << " |";
    m << "\n|---|";
    for (std::size_t i = 0; i < r.names.size(); ++i) m << "---|";
    m << "\n";
    for (std::size_t i = 0; i < r.names.size(); ++i) {
      m << "| " << r.names[i] << " |";
      for (std::size_t k = 0; k < r.names.size(); ++k)
        m << " " << shortNumber(r.corr(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)), 3) << " |";
      m << "\n";
    }
    m << "\n";
  } else {
    m << "No standard deviations or correlations: " << r.covarianceMessage << ".\n\n";
  }
  return m.str();
}

std::string residualsSection(const Calibration& c, const FitResult& r, const std::string& note) {
  std::ostringstream m;
  m << "## Residuals (simulated - measured) per channel\n\n| measurement | channel | unit | fitted | before: mean | RMS | "
       "max abs | after: mean | RMS | max abs (at t [s]) | lag-1 autocorrelation |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < c.measurements.size(); ++k) {
    const Measurement& me = c.measurements[k];
    const MeasurementFit& f = r.measurements[k];
    for (std::size_t i = 0; i < me.channels.size(); ++i) {
      const ChannelStats &b = f.statsBefore[i], &a = f.statsAfter[i];
      m << "| " << me.name << " | " << me.channels[i].name << " | " << me.channels[i].unit << " | "
        << (me.channels[i].fitted() ? "yes" : "no") << " | " << shortNumber(b.mean, 3) << " | " << shortNumber(b.rms, 3) << " | "
        << shortNumber(b.maxAbs, 3) << " | " << shortNumber(a.mean, 3) << " | " << shortNumber(a.rms, 3) << " | "
        << shortNumber(a.maxAbs, 3) << " (" << shortNumber(a.tMaxAbs, 4) << ") | " << shortNumber(a.lag1, 3) << " |\n";
    }
  }
  m << "\n";
  for (const Measurement& me : c.measurements) {
    m << "### " << me.name << "\n\n";
    if (note.empty())
      m << "![" << me.name << "](plots/" << me.name << ".png)\n\nLeft: measured (grey points) against the simulation at "
        << "the initial values (dashed) and at the fitted values (line); right: the residuals before and after.\n\n";
    m << "Data: `histories_" << me.name << ".csv`.\n\n";
  }
  return m.str();
}

std::string figureScript(const Calibration& c, std::size_t k) {
  const Measurement& me = c.measurements[k];
  const std::size_t n = me.channels.size();
  const std::string data = gpString("../histories_" + me.name + ".csv");
  std::ostringstream g;
  g << "reset\nset terminal pngcairo size 1300," << 280 * n + 60 << " noenhanced\nset output " << gpString(me.name + ".png")
    << "\nset datafile separator ','\nset multiplot layout " << n << ",2 title "
    << gpString("calibration " + c.name + ", measurement " + me.name + ": measured against simulated") << "\nset grid\n"
    << "set key top right font ',9'\nset xlabel 't [s]'\n";
  for (std::size_t i = 0; i < n; ++i) {
    const Channel& ch = me.channels[i];
    const int mc = 3 + 4 * static_cast<int>(i);  // measured, initial, fitted, residual
    g << "set title " << gpString(ch.name + " [" + ch.unit + "]" + (ch.fitted() ? "" : " (compared, not fitted)")) << "\n"
      << "plot " << data << " every ::1 using 1:" << mc << " with points pt 7 ps 0.3 lc rgb '#999999' title 'measured', "
      << data << " every ::1 using 1:" << mc + 1 << " with lines dt 2 lw 1.5 lc rgb '#ff7f0e' title 'initial', " << data
      << " every ::1 using 1:" << mc + 2 << " with lines lw 2 lc rgb '#1f77b4' title 'fitted'\n"
      << "set title " << gpString(ch.name + ": simulated - measured [" + ch.unit + "]") << "\n"
      << "plot " << data << " every ::1 using 1:($" << mc + 1 << "-$" << mc << ") with lines dt 2 lc rgb '#ff7f0e' title 'initial', "
      << data << " every ::1 using 1:" << mc + 3 << " with lines lc rgb '#1f77b4' title 'fitted'\n";
  }
  return g.str() + "unset multiplot\n";
}

}  // namespace

std::string reportMarkdown(const Calibration& c, const FitResult& r, const std::string& note) {
  std::ostringstream m;
  m << "# Calibration: " << c.name << "\n\n- calibration file: `" << c.file << "`\n- scene: `" << c.sceneFile
    << "`\n- outcome: **" << outcome(r) << "**; Ceres (Levenberg-Marquardt, dense QR): " << r.termination << " after "
    << r.iterations << " iterations (" << r.ceresMessage << "); cost (sum of rho(r^2)/2) " << shortNumber(r.initialCost, 6)
    << " -> " << shortNumber(r.finalCost, 6) << "; every measurement simulated at " << r.evaluations << " points\n- loss: "
    << lossName(c.fit.loss) << (c.fit.loss == Loss::None ? "" : " (scale " + shortNumber(c.fit.lossScale) + ")") << "\n\n";
  if (!r.warnings.empty()) {
    m << "Warnings:\n\n";
    for (const auto& w : r.warnings) m << "- " << w << "\n";
    m << "\n";
  }
  m << parametersSection(c, r) << measurementsSection(c, r) << residualsSection(c, r, note);
  m << "## Files\n\n`result.json`; `calibrated.toml` (the scene with the fitted values: `simulate calibrated.toml`); "
       "`histories_<measurement>.csv` (per sample: measured, initial, fitted, residual, units in the header); `plots/` "
       "(gnuplot scripts" << (note.empty() ? " and pictures)" : ")") << ".\n";
  if (!note.empty()) m << "\n" << note << "\n";
  return m.str();
}

CalibrationFiles writeCalibration(const Calibration& c, const FitResult& r, const std::string& dir, bool plots,
                                  const Provenance* provenance) {
  CalibrationFiles out;
  const fs::path d(dir), pd = d / "plots";
  fs::create_directories(pd);
  auto put = [&](const fs::path& p, const std::string& text) {
    writeFileAtomic(p.string(), text);
    out.written.push_back(fs::relative(p, d).string());
  };
  std::string script;
  for (std::size_t k = 0; k < c.measurements.size(); ++k) {
    put(d / ("histories_" + c.measurements[k].name + ".csv"), historiesCsv(c, r, k));
    script += figureScript(c, k);
  }
  put(pd / "plots.gp", script);
  std::string note;
  if (!plots) note = "Pictures were not requested: run `gnuplot plots.gp` in `plots/` to draw them.";
  else if (!haveGnuplot()) note = "gnuplot was not found: run `gnuplot plots.gp` in `plots/` to draw the pictures.";
  else if (std::system(("cd '" + pd.string() + "' && gnuplot plots.gp > gnuplot.log 2>&1").c_str()) != 0)
    note = "gnuplot failed (see `plots/gnuplot.log`); the data and the scripts are in `plots/`.";
  if (!note.empty() && plots) out.warnings.push_back(note);
  put(d / "calibrated.toml", stampToml(calibratedToml(c, r, dir), provenance));
  put(d / "result.json", stampJson(resultJson(c, r), provenance));
  put(d / "report.md", stampMarkdown(reportMarkdown(c, r, note), provenance));
  return out;
}

}  // namespace lg::calib
