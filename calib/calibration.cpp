// Calibration files: parsing and validation at the edge (calibration.hpp).
#include "calib/calibration.hpp"

#include <cmath>
#include <filesystem>
#include <set>

#include "sim/io/csv_table.hpp"
#include "sim/io/drop_case.hpp"
#include "sim/io/overrides.hpp"  // applySolverTable
#include "sim/scene/parameters.hpp"  // parameterUnit
#include "sim/io/files.hpp"
#include "sim/io/toml_reader.hpp"

namespace fs = std::filesystem;

namespace lg::calib {

std::size_t Measurement::residuals() const {
  std::size_t n = 0;
  for (const auto& c : channels) n += c.fitted() ? t.size() : 0;
  return n;
}

std::size_t Calibration::unknowns() const {
  std::size_t n = parameters.size();
  for (const auto& m : measurements) n += m.shift.fit ? 1 : 0;
  return n;
}

std::size_t Calibration::residuals() const {
  std::size_t n = 0;
  for (const auto& m : measurements) n += m.residuals();
  return n;
}

const char* lossName(Loss l) {
  switch (l) {
    case Loss::Huber: return "huber";
    case Loss::Cauchy: return "cauchy";
    case Loss::SoftL1: return "soft_l1";
    case Loss::Arctan: return "arctan";
    default: return "none";
  }
}

namespace {

// A path in the calibration file, relative to its folder.
std::string resolve(const std::string& baseDir, const std::string& rel) {
  fs::path p(rel);
  if (p.is_relative()) p = fs::path(baseDir) / p;
  return p.lexically_normal().string();
}

// [[parameter]]
void parseParameters(const toml::table& doc, const std::string& file, Calibration& c) {
  const auto rows = tablesOf(doc, "parameter", file);
  if (rows.empty()) throw InputError(file, 0, "parameter", "a calibration needs at least one [[parameter]] to fit");
  std::set<std::string> paths;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    TomlReader r(*rows[i], file, "parameter[" + std::to_string(i) + "]");
    r.allowOnly({"path", "lower", "upper", "initial"});
    FitParameter p;
    p.line = r.line();
    p.path = r.string("path");
    if (!paths.insert(p.path).second) r.fail("path", "'" + p.path + "' is already a parameter of this calibration");
    double sceneValue = 0;
    try {
      p.parameter = resolveParameter(c.scene, p.path, c.sceneFile);
    } catch (const InputError& e) {
      r.fail("path", "'" + p.path + "' is not a numeric parameter of the scene (" + e.what() + ")");
    }
    if (p.parameter.kind == Parameter::Kind::Case && p.parameter.key == "duration")
      r.fail("path", "a case's duration is no parameter of the drop: it cannot be fitted");
    try {
      sceneValue = parameterValue(c.scene, p.parameter);
      toml::table doc = c.scene.doc;  // calibrated.toml writes it: the file must hold the key (a table's sample inline)
      inlineTables(doc, c.scene, {p.path});
      (void)getParameter(doc, p.path, c.sceneFile);
    } catch (const InputError& e) {
      r.fail("path", "'" + p.path + "' is not a numeric parameter of the scene file (" + e.what() + ")");
    }
    p.unit = parameterUnit(p.path);
    p.lower = r.number("lower");
    p.upper = r.number("upper");
    if (!(p.upper > p.lower)) r.fail("upper", "upper " + fmt(p.upper) + " must be greater than lower " + fmt(p.lower));
    for (const char* bound : {"lower", "upper"})
      if (const auto why = ownRuleBroken(c.scene, p.parameter, r.number(bound)))
        r.fail(bound, "value " + fmt(r.number(bound)) + " breaks the rule of " + p.path + ": " + *why +
                          " (a bound is a value the fit may take)");
    p.initial = r.has("initial") ? r.number("initial") : sceneValue;
    if (!(p.initial >= p.lower && p.initial <= p.upper))
      r.fail(r.has("initial") ? "initial" : "path",
             (r.has("initial") ? "initial " : "the scene value (the default initial) ") + fmt(p.initial) +
                 " must lie in [lower, upper] = [" + fmt(p.lower) + ", " + fmt(p.upper) + "]");
    p.scale = p.initial != 0 ? std::abs(p.initial) : p.upper - p.lower;
    c.parameters.push_back(p);
  }
}

// The drop of a measurement: a scene case as is, a scene case with overrides, or an inline one.
void parseCase(const TomlReader& r, const Calibration& c, Measurement& m) {
  const bool overrides = !dropCaseKey(r).empty();
  if (r.has("case")) {
    const std::string name = r.string("case");
    std::string list;
    for (std::size_t k = 0; k < c.scene.cases.size(); ++k) {
      if (c.scene.cases[k].name == name) m.sceneCase = static_cast<int>(k);
      list += (list.empty() ? "" : ", ") + c.scene.cases[k].name;
    }
    if (m.sceneCase < 0)
      r.fail("case", "'" + name + "' is not a case of the scene (there are: " + (list.empty() ? "none" : list) +
                         "); or give the drop inline: sink_speed, lift_ratio (duration, masses)");
    m.dropCase = c.scene.cases[static_cast<std::size_t>(m.sceneCase)];
    if (overrides) m.sceneCase = -1;  // its own drop now: the scene's case parameters no longer reach it
  } else {
    if (!r.has("sink_speed") && !r.has("drop_height"))
      r.fail("case", "missing: name a case of the scene (case = \"limit\") or give the drop inline (sink_speed, lift_ratio)");
    if (!r.has("lift_ratio")) r.fail("lift_ratio", "missing required number (an inline drop needs sink_speed and lift_ratio)");
    m.dropCase.name = m.name;
  }
  readDropCase(r, c.scene, m.dropCase, !r.has("case"));  // (sim/io/drop_case.hpp)
}

// A table of channel = number (weights, sigma); each channel must be one of 'columns'.
std::vector<std::pair<std::string, double>> channelNumbers(const TomlReader& r, const std::string& file, const std::string& key,
                                                           const std::vector<Channel>& channels) {
  std::vector<std::pair<std::string, double>> out;
  const toml::node* n = r.get(key);
  if (!n) return out;
  const toml::table* t = n->as_table();
  if (!t) r.fail(key, "must be a table of channel = number, e.g. { P_y = 1.0e-3 }");
  const TomlReader tr(*t, file, r.full(key));
  for (const auto& [k, v] : *t) {
    const std::string ch(k.str());
    bool known = false;
    for (const auto& c : channels) known = known || c.name == ch;
    if (!known) tr.fail(ch, "'" + ch + "' is not a channel of 'columns'");
    const double x = tr.number(ch);
    if (!(x > 0)) tr.fail(ch, "value " + fmt(x) + " must be > 0");
    out.emplace_back(ch, x);
  }
  return out;
}

// columns: the channels (without weights yet) and the CSV's time column.
std::string parseColumns(const TomlReader& r, const TomlReader& cr, const toml::table& ct, const Calibration& c, Measurement& m) {
  const std::vector<Column> history = historyColumns(c.scene);
  std::string allowed;
  for (const auto& h : history) allowed += ", " + h.name;
  std::string timeColumn;
  for (const auto& [k, v] : ct) {
    const std::string ch(k.str());
    if (!v.is_string() || v.value<std::string>()->empty())
      cr.fail(ch, "must be the name of a CSV column (a non-empty string)");
    const std::string csv(*v.value<std::string>());
    if (ch == "t") {
      timeColumn = csv;
      continue;
    }
    Channel chan;
    chan.name = ch;
    chan.csvColumn = csv;
    for (std::size_t h = 0; h < history.size(); ++h)
      if (history[h].name == ch && ch != "violation") {
        chan.historyColumn = static_cast<int>(h);
        chan.unit = history[h].unit;
      }
    if (chan.historyColumn < 0)
      cr.fail(ch, "'" + ch + "' is not a channel of the scene's time histories (allowed: t" +
                      allowed.substr(0, allowed.rfind(", violation")) + ")");
    m.channels.push_back(chan);
  }
  if (timeColumn.empty()) r.fail("columns", "missing the time column: t = \"<CSV column>\" [s]");
  if (m.channels.empty()) r.fail("columns", "names no channel to compare besides t");
  return timeColumn;
}

// weights and sigma of the channels.
void parseWeights(const TomlReader& r, const Calibration& c, Measurement& m) {
  const auto weights = channelNumbers(r, c.file, "weights", m.channels), sigmas = channelNumbers(r, c.file, "sigma", m.channels);
  for (auto& ch : m.channels) {
    for (const auto& [name, w] : weights)
      if (name == ch.name) ch.weight = w;
    for (const auto& [name, s] : sigmas)
      if (name == ch.name) {
        if (ch.weight > 0)
          TomlReader(*r.get("sigma")->as_table(), c.file, r.full("sigma"))
              .fail(name, "channel '" + name + "' has a weight already: give a weight or a sigma, not both");
        ch.sigma = s;
        ch.weight = 1 / s;
      }
  }
}

// The CSV: its times, its channels, its length against the case's. The mistakes in the calibration file
// (a column the CSV lacks) name it, those in the rows name the CSV.
void readCsv(const TomlReader& cr, const std::string& timeColumn, Measurement& m) {
  std::string example = timeColumn;
  for (const auto& ch : m.channels) example += "," + ch.csvColumn;
  const CsvTable csv(m.file, "measurement file", example, " (measurement '" + m.name + "' of " + cr.file() + ")");
  const int tk = csv.column(timeColumn);
  if (tk < 0)
    cr.fail("t", "column '" + timeColumn + "' is not in the header of '" + m.file + "' (its columns: " + csv.headerList() + ")");
  std::vector<int> ks;
  for (const auto& ch : m.channels) {
    const int k = csv.column(ch.csvColumn);
    if (k < 0)
      cr.fail(ch.name, "column '" + ch.csvColumn + "' is not in the header of '" + m.file + "' (its columns: " +
                           csv.headerList() + ")");
    ks.push_back(k);
  }
  if (csv.rows() < 2)
    csv.fail(-1, "header", "the file has " + std::to_string(csv.rows()) + " rows of samples: a measurement needs at least 2");
  m.t = csv.numbers(tk);
  for (std::size_t i = 1; i < m.t.size(); ++i)
    if (!(m.t[i] > m.t[i - 1]))
      throw InputError(m.file, csv.rowLine(i), timeColumn, "time " + fmt(m.t[i]) + " s must be greater than the previous sample's " +
                                                           fmt(m.t[i - 1]) + " s (times increase strictly)");
  for (int k : ks) m.y.push_back(csv.numbers(k));
  // Longer than the simulated drop: the last sample must fall within the case for every shift allowed.
  const double last = m.t.back() - m.shift.lower;
  if (last > m.dropCase.duration)
    throw InputError(m.file, csv.rowLine(csv.rows() - 1), timeColumn,
                     "time " + fmt(m.t.back()) + " s is " + fmt(last) + " s after touchdown (t - t_shift" +
                         (m.shift.fit ? ", t_shift from " + fmt(m.shift.lower) + " s" : " = " + fmt(m.shift.value) + " s") +
                         "), beyond the end of case '" + m.dropCase.name + "' (duration " + fmt(m.dropCase.duration) +
                         " s): a measurement may not be longer than its simulated drop (give the measurement a longer "
                         "duration, or cut the file)");
}

// columns, weights, sigma; then the CSV itself.
void parseChannels(const TomlReader& r, const Calibration& c, Measurement& m) {
  const toml::node* cn = r.get("columns");
  if (!cn) r.fail("columns", "missing: which CSV column holds what, e.g. { t = \"time_s\", P_y = \"Fz_N\" }");
  const toml::table* ct = cn->as_table();
  if (!ct) r.fail("columns", "must be a table of channel = \"CSV column\", e.g. { t = \"time_s\", P_y = \"Fz_N\" }");
  const TomlReader cr(*ct, c.file, r.full("columns"));
  const std::string timeColumn = parseColumns(r, cr, *ct, c, m);
  parseWeights(r, c, m);
  readCsv(cr, timeColumn, m);
}

// t_shift and t_shift_range.
void parseShift(const TomlReader& r, Measurement& m) {
  const toml::node* n = r.get("t_shift");
  if (n && n->is_string()) {
    if (*n->value<std::string>() != "fit")
      r.fail("t_shift", "value '" + std::string(*n->value<std::string>()) + "' must be \"fit\" or a time [s]");
    m.shift.fit = true;
    m.shift.lower = -0.01;
    m.shift.upper = 0.01;
    if (const toml::node* rn = r.get("t_shift_range")) {
      const toml::array* a = rn->as_array();
      if (!a || a->size() != 2) r.fail("t_shift_range", "must be [lower, upper] in s");
      m.shift.lower = r.toNumber(*a->get(0), "t_shift_range");
      m.shift.upper = r.toNumber(*a->get(1), "t_shift_range");
      if (!(m.shift.upper > m.shift.lower))
        r.fail("t_shift_range", "upper " + fmt(m.shift.upper) + " s must be greater than lower " + fmt(m.shift.lower) + " s");
    }
    m.shift.value = 0.5 * (m.shift.lower + m.shift.upper);
    return;
  }
  if (r.has("t_shift_range")) r.fail("t_shift_range", "only with t_shift = \"fit\"");
  m.shift.value = m.shift.lower = m.shift.upper = r.number("t_shift", 0.0);
}

// [[measurement]]
void parseMeasurements(const toml::table& doc, const std::string& file, const std::string& baseDir, Calibration& c) {
  const auto rows = tablesOf(doc, "measurement", file);
  if (rows.empty()) throw InputError(file, 0, "measurement", "a calibration needs at least one [[measurement]]");
  std::set<std::string> names;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    TomlReader r(*rows[i], file, "measurement[" + std::to_string(i) + "]");
    r.allowOnly({"name", "file", "case", "sink_speed", "drop_height", "lift_ratio", "duration", "forward_speed", "masses",
                 "columns", "weights", "sigma", "t_shift", "t_shift_range"});
    Measurement m;
    m.line = r.line();
    m.file = resolve(baseDir, r.string("file"));
    if (const std::string why = fileProblem(m.file); !why.empty())
      r.fail("file", "cannot read the measurement file '" + m.file + "': " + why + " (the path is relative to the calibration file)");
    const std::string stem = safeFileStem(fs::path(m.file).stem().string());
    if (!r.has("name") && !isName(stem))
      r.fail("file", "the file's stem '" + stem + "' cannot name the measurement (" + nameRule() + "): give name = \"...\"");
    m.name = r.name("name", stem);
    if (!names.insert(m.name).second)
      r.fail(r.has("name") ? "name" : "file", "measurement '" + m.name + "' appears twice: give each a name = \"...\"");
    parseCase(r, c, m);
    parseShift(r, m);
    parseChannels(r, c, m);
    c.measurements.push_back(std::move(m));
  }
}

// [fit]
void parseFit(const toml::table& doc, const std::string& file, Calibration& c) {
  const toml::table* t = tableOf(doc, "fit", file);
  if (!t) return;
  TomlReader r(*t, file, "fit");
  r.allowOnly({"jacobian", "loss", "loss_scale", "max_iterations", "jacobian_step", "shift_step", "function_tolerance",
               "parameter_tolerance", "gradient_tolerance", "identifiability"});
  FitSettings& f = c.fit;
  const std::string jacobian = r.string("jacobian", "exact");
  if (jacobian != "exact" && jacobian != "central")
    r.fail("jacobian", "value '" + jacobian + "' must be \"exact\" (forward mode through the drop test) or \"central\" "
                       "(central differences with jacobian_step and shift_step)");
  f.exactJacobian = jacobian == "exact";
  for (const char* key : {"jacobian_step", "shift_step"})
    if (f.exactJacobian && r.has(key))
      r.fail(key, "a step of the central differences, for jacobian = \"central\"; the exact Jacobian takes none");
  const std::string loss = r.string("loss", "none");
  bool found = false;
  for (Loss l : {Loss::None, Loss::Huber, Loss::Cauchy, Loss::SoftL1, Loss::Arctan})
    if (loss == lossName(l)) {
      f.loss = l;
      found = true;
    }
  if (!found) r.fail("loss", "value '" + loss + "' must be \"none\", \"huber\", \"cauchy\", \"soft_l1\" or \"arctan\"");
  if (r.has("loss_scale") && f.loss == Loss::None) r.fail("loss_scale", "only with a robust loss (loss = \"huber\", ...)");
  f.lossScale = r.positive("loss_scale", f.lossScale);
  f.maxIterations = static_cast<int>(r.count("max_iterations", f.maxIterations, 1, 10000));
  f.jacobianStep = r.positive("jacobian_step", f.jacobianStep);
  if (f.jacobianStep > 0.1) r.fail("jacobian_step", "value " + fmt(f.jacobianStep) + " must be <= 0.1 (a relative step)");
  f.shiftStep = r.positive("shift_step", f.shiftStep);
  f.functionTolerance = r.positive("function_tolerance", f.functionTolerance);
  f.parameterTolerance = r.positive("parameter_tolerance", f.parameterTolerance);
  f.gradientTolerance = r.positive("gradient_tolerance", f.gradientTolerance);
  f.identifiability = r.positive("identifiability", f.identifiability);
  if (f.identifiability >= 1) r.fail("identifiability", "value " + fmt(f.identifiability) + " must be < 1 (a reciprocal condition number)");
}

}  // namespace

Calibration parseCalibration(const std::string& text, const std::string& file, const std::string& baseDir,
                             const std::vector<ParameterOverride>& sets) {
  const toml::table doc = parseToml(text, file);
  Calibration c;
  c.file = file;
  TomlReader top(doc, file, "");
  top.allowOnly({"name", "description", "scene", "solver", "measurement", "parameter", "fit"});
  c.name = top.name("name", safeFileStem(fs::path(file).stem().string()));
  (void)top.string("description", "");
  {
    const std::string p = resolve(baseDir, top.string("scene"));
    if (const std::string why = fileProblem(p); !why.empty())
      top.fail("scene", "cannot read the scene file '" + p + "': " + why + " (the path is relative to the calibration file)");
    c.sceneFile = p;
    c.sceneDir = fs::path(p).parent_path().lexically_normal().string();
    if (c.sceneDir.empty()) c.sceneDir = ".";
    c.scene = applyOverrides(loadScene(c.sceneFile), sets);  // its own errors name the scene file
  }
  applySolverTable(tableOf(doc, "solver", file), file, c.scene);
  parseParameters(doc, file, c);
  parseFit(doc, file, c);
  parseMeasurements(doc, file, baseDir, c);

  const std::size_t m = c.residuals(), n = c.unknowns();
  if (m == 0)
    throw InputError(file, 0, "measurement", "no channel is fitted: give a weight or a sigma to at least one channel");
  if (m <= n)
    throw InputError(file, 0, "measurement", std::to_string(m) + " fitted samples cannot determine " + std::to_string(n) +
                                                 " unknowns (the parameters and the fitted t_shift): more are needed");
  for (std::size_t i = 0; i < c.measurements.size(); ++i)
    if (c.measurements[i].shift.fit && c.measurements[i].residuals() == 0)
      throw InputError(file, c.measurements[i].line, "measurement[" + std::to_string(i) + "].t_shift",
                       "a fitted t_shift needs a fitted channel of its own measurement (a weight or a sigma)");
  // The scene must accept the initial design.
  Scene start = c.scene;
  std::vector<Parameter> ps;
  std::vector<double> x0;
  for (const auto& p : c.parameters) {
    ps.push_back(p.parameter);
    x0.push_back(p.initial);
  }
  if (const auto why = applyParameters(start, ps, x0)) {
    // Named at the parameter at fault: the first the scene rejects on its own, else all of them together.
    for (std::size_t k = 0; k < ps.size(); ++k) {
      Scene one = c.scene;
      if (const auto alone = applyParameters(one, {ps[k]}, {x0[k]}))
        throw InputError(file, c.parameters[k].line, "parameter[" + std::to_string(k) + "]",
                         "the scene rejects " + c.parameters[k].parameter.path + " = " + fmt(x0[k]) + ": " + *alone);
    }
    throw InputError(file, c.parameters[0].line, "parameter", "the scene rejects the initial values together: " + *why);
  }
  return c;
}

Calibration loadCalibration(const std::string& path, const std::vector<ParameterOverride>& sets) {
  const std::string text = readText(path, "calibration file");
  std::string base = fs::path(path).parent_path().string();
  if (base.empty()) base = ".";
  return parseCalibration(text, path, base, sets);
}

}  // namespace lg::calib
