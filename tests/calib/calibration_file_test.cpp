// Calibration files and measurement CSVs (calib/calibration.hpp): what a valid file says, and every
// mistake one error naming the file (the calibration file, or the CSV for its rows), the line, the key and
// the rule; the program then exits 2 and writes nothing.
#include "calib_support.hpp"  // project headers, then Catch

#include <regex>

using namespace calibtest;

namespace {

const std::string kSigma = "sigma = { P_y = 500.0, s = 2e-4, h = 2e-4 }";
const std::string kF1 = parameter("strut.f1", 3e-5, 1.6e-4);

// A folder with drop.csv (0 .. 0.3 s at 2 kHz, noise-free) and c.cfg.
struct Files {
  TempDir dir{"file"};
  std::string csv = limitCsv({}, 0.0, 0, 1);
  void write(const std::string& extra, const std::string& rest) const {
    writeFile(dir / "drop.csv", csv);
    writeFile(dir / "c.cfg", calibText("drop.csv", extra, rest));
  }
  // The CSV with line 'line' (1-based) replaced.
  void replaceLine(int line, const std::string& text) {
    std::size_t at = 0;
    for (int k = 1; k < line; ++k) at = csv.find('\n', at) + 1;
    csv.replace(at, csv.find('\n', at) - at, text);
  }
};

struct Expected {
  std::string file;  // "cfg" or "csv"
  int line;
  std::string key, rule;
};

void expectError(const Files& f, const Expected& e) {
  try {
    (void)lg::calib::loadCalibration(f.dir / "c.cfg");
    FAIL("no error; expected " << e.key << ": " << e.rule);
  } catch (const lg::InputError& err) {
    INFO(err.what());
    CHECK(err.file() == (e.file == "cfg" ? f.dir / "c.cfg" : f.dir / "drop.csv"));
    CHECK(err.line() == e.line);
    CHECK(err.key() == e.key);
    CHECK(std::string(err.what()).find(e.rule) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("calibration files: a valid file as the fit sees it", "[calib][file]") {
  Files f;
  f.write(kSigma + "\nt_shift = \"fit\"\nt_shift_range = [-0.002, 0.004]\n",
          kF1 + parameter("tyre.K", 5e5, 1.2e6) + "initial = 9e5\n[fit]\njacobian = \"central\"\nloss = \"huber\"\nloss_scale = 2.0\njacobian_step = 1e-3\n");
  const lg::calib::Calibration c = lg::calib::loadCalibration(f.dir / "c.cfg");
  CHECK(c.name == "c");
  REQUIRE(c.parameters.size() == 2);
  CHECK(c.parameters[0].path == "strut.f1");
  CHECK(c.parameters[0].unit == "m^2");
  CHECK(c.parameters[0].initial == 7e-5);  // the scene's value
  CHECK(c.parameters[0].scale == 7e-5);
  CHECK(c.parameters[1].initial == 9e5);
  REQUIRE(c.measurements.size() == 1);
  const lg::calib::Measurement& m = c.measurements[0];
  CHECK(m.name == "drop");  // the CSV's stem
  CHECK(m.sceneCase == -1);
  CHECK(m.dropCase.name == "drop");
  CHECK(m.dropCase.sinkSpeed == 3.05);
  CHECK(m.dropCase.duration == 0.35);
  REQUIRE(m.channels.size() == 3);  // in the order of the TOML table's keys
  CHECK(m.channels[0].name == "P_y");
  CHECK(m.channels[0].unit == "N");
  CHECK(m.channels[0].csvColumn == "Fz_N");
  CHECK(m.channels[0].weight == 1 / 500.0);
  CHECK(m.channels[2].name == "s");
  CHECK(m.channels[2].sigma == 2e-4);
  CHECK(m.t.size() == 601);
  CHECK(m.t[1] == 0.0005);
  CHECK(m.shift.fit);
  CHECK(m.shift.lower == -0.002);
  CHECK(m.shift.upper == 0.004);
  CHECK(m.shift.value == 0.001);  // the middle of the range
  CHECK(c.residuals() == 3 * 601);
  CHECK(c.unknowns() == 3);
  CHECK(c.fit.loss == lg::calib::Loss::Huber);
  CHECK(c.fit.lossScale == 2.0);
  CHECK(c.fit.jacobianStep == 1e-3);
  // A scene case by name: the case parameters of the scene reach it; a channel without a weight or a
  // sigma is compared, not fitted.
  Files g;
  g.csv = limitCsv({}, 0.0, 0, 1, 0, 0.3);
  writeFile(g.dir / "drop.csv", g.csv);
  writeFile(g.dir / "c.cfg", "scene = \"" + sourcePath("data/seed_gear.toml") +
                                 "\"\n[[measurement]]\nname = \"rig_3\"\nfile = \"drop.csv\"\ncase = \"limit\"\n"
                                 "columns = { t = \"time_s\", P_y = \"Fz_N\", s = \"stroke_m\" }\nweights = { P_y = 1e-3 }\n" +
                                 parameter("limit.sink_speed", 2.5, 3.5));
  const lg::calib::Calibration d = lg::calib::loadCalibration(g.dir / "c.cfg");
  CHECK(d.measurements[0].name == "rig_3");
  CHECK(d.measurements[0].sceneCase >= 0);
  CHECK(d.measurements[0].dropCase.duration == 0.8);
  CHECK(d.measurements[0].channels[0].fitted());
  CHECK_FALSE(d.measurements[0].channels[1].fitted());
  CHECK(d.residuals() == 601);
}

TEST_CASE("calibration files: mistakes in the calibration file name its line and key", "[calib][file]") {
  // Lines of calibText: 7 columns, 8 the measurement's extra line, 9.. the rest ([[parameter]] at 9).
  struct Case {
    std::string extra, rest;
    Expected e;
  };
  const std::vector<Case> cases{
      {kSigma, kF1 + "colour = 3\n", {"cfg", 13, "parameter[0].colour", "unknown key"}},
      {kSigma, parameter("strut.nope", 1, 2), {"cfg", 10, "parameter[0].path", "not a numeric parameter of the scene"}},
      {kSigma, parameter("nothing.f1", 1, 2), {"cfg", 10, "parameter[0].path", "no body, stop, force element or case"}},
      {kSigma, parameter("strut.f1", 2e-4, 1e-4), {"cfg", 12, "parameter[0].upper", "must be greater than lower"}},
      {kSigma, parameter("strut.f1", -1e-5, 1e-4) + "initial = 7e-5\n",
       {"cfg", 11, "parameter[0].lower", "value -1e-05 breaks the rule of strut.f1: "}},
      {kSigma, kF1 + "initial = 2e-4\n", {"cfg", 13, "parameter[0].initial", "must lie in [lower, upper]"}},
      {kSigma, parameter("strut.f1", 8e-5, 1e-4), {"cfg", 10, "parameter[0].path", "the scene value (the default initial) 7e-05"}},
      {kSigma, kF1 + kF1, {"cfg", 14, "parameter[1].path", "already a parameter"}},
      {kSigma, "", {"cfg", 0, "parameter", "at least one [[parameter]]"}},
      {kSigma, parameter("limit.duration", 0.5, 1), {"cfg", 10, "parameter[0].path", "cannot be fitted"}},
      {kSigma, parameter("strut.Omega0", 1e-3, 2e-3) + "initial = 1.1e-3\n",
       {"cfg", 9, "parameter[0]", "the scene rejects strut.Omega0 = 0.0011: "}},
      // named at the parameter at fault, not at the first one
      {kSigma, kF1 + parameter("strut.Omega0", 1e-3, 2e-3) + "initial = 1.1e-3\n",
       {"cfg", 13, "parameter[1]", "the scene rejects strut.Omega0 = 0.0011: "}},
      {"sigma = { P_y = 500.0, delta = 1e-3 }", kF1, {"cfg", 8, "measurement[0].sigma.delta", "not a channel of 'columns'"}},
      {"sigma = { P_y = -5.0 }", kF1, {"cfg", 8, "measurement[0].sigma.P_y", "must be > 0"}},
      {"weights = { P_y = 1e-3 }\nsigma = { P_y = 500.0 }", kF1,
       {"cfg", 9, "measurement[0].sigma.P_y", "give a weight or a sigma, not both"}},
      {"", kF1, {"cfg", 0, "measurement", "no channel is fitted"}},
      {kSigma + "\nt_shift = \"guess\"", kF1, {"cfg", 9, "measurement[0].t_shift", "must be \"fit\" or a time"}},
      {kSigma + "\nt_shift_range = [0.0, 0.01]", kF1, {"cfg", 9, "measurement[0].t_shift_range", "only with t_shift = \"fit\""}},
      {kSigma + "\nt_shift = \"fit\"\nt_shift_range = [0.01, 0.0]", kF1,
       {"cfg", 10, "measurement[0].t_shift_range", "must be greater than lower"}},
      {kSigma + "\ncolums = 1", kF1, {"cfg", 9, "measurement[0].colums", "unknown key"}},
      {kSigma + "\ncase = \"nope\"", kF1, {"cfg", 9, "measurement[0].case", "not a case of the scene"}},
      {kSigma + "\nmasses = { nobody = 3.0 }", kF1, {"cfg", 9, "measurement[0].masses.nobody", "'nobody' is not a body"}},
      // the drop's keys by the scene's reader and rules (sim/io/drop_case.hpp)
      {kSigma + "\nforward_speed = 10.0", kF1,
       {"cfg", 9, "measurement[0].forward_speed", "no tyre of this scene declares the longitudinal friction coefficient mu_x"}},
      {kSigma + "\ndrop_height = -0.1", kF1, {"cfg", 9, "measurement[0].drop_height", "value -0.1 must be >= 0"}},
      {kSigma, kF1 + "[fit]\nloss = \"l2\"\n", {"cfg", 14, "fit.loss", "must be \"none\", \"huber\""}},
      {kSigma, kF1 + "[fit]\njacobian = \"central\"\njacobian_step = 0.5\n", {"cfg", 15, "fit.jacobian_step", "must be <= 0.1"}},
      {kSigma, kF1 + "[fit]\nloss_scale = 2.0\n", {"cfg", 14, "fit.loss_scale", "only with a robust loss"}},
      {kSigma, kF1 + "[fit]\njacobian = \"numeric\"\n", {"cfg", 14, "fit.jacobian", "must be \"exact\""}},
      {kSigma, kF1 + "[fit]\nshift_step = 1e-6\n", {"cfg", 14, "fit.shift_step", "for jacobian = \"central\""}},
      {kSigma, kF1 + "[solver]\nintegrator = \"leapfrog\"\n", {"cfg", 14, "solver.integrator", "must be one of"}},
  };
  for (const Case& c : cases) {
    INFO(c.extra << "\n" << c.rest);
    Files f;
    f.write(c.extra, c.rest);
    expectError(f, c.e);
  }
}

TEST_CASE("calibration files: columns, times and samples of the CSV", "[calib][file]") {
  {  // a column the CSV lacks: the mistake is the calibration file's
    Files f;
    writeFile(f.dir / "drop.csv", f.csv);
    std::string text = calibText("drop.csv", kSigma, kF1);
    text.replace(text.find("\"Fz_N\""), 6, "\"Fy_N\"");
    writeFile(f.dir / "c.cfg", text);
    expectError(f, {"cfg", 7, "measurement[0].columns.P_y", "column 'Fy_N' is not in the header of"});
    CHECK_THROWS_WITH(lg::calib::loadCalibration(f.dir / "c.cfg"), Catch::Contains("its columns: time_s, Fz_N, stroke_m, travel_m"));
  }
  {  // a channel the scene's histories do not have
    Files f;
    writeFile(f.dir / "drop.csv", f.csv);
    std::string text = calibText("drop.csv", kSigma, kF1);
    text.replace(text.find("h = \"travel_m\""), 14, "z = \"travel_m\"");
    writeFile(f.dir / "c.cfg", text);
    expectError(f, {"cfg", 7, "measurement[0].columns.z", "not a channel of the scene's time histories"});
  }
  {  // no time column
    Files f;
    writeFile(f.dir / "drop.csv", f.csv);
    std::string text = calibText("drop.csv", kSigma, kF1);
    text.replace(text.find("t = \"time_s\", "), 14, "");
    writeFile(f.dir / "c.cfg", text);
    expectError(f, {"cfg", 7, "measurement[0].columns", "missing the time column"});
  }
  {  // times that do not increase: row 51 (line 52) repeats the time of row 50
    Files f;
    f.replaceLine(52, "0.0245,1,0,0");
    f.write(kSigma, kF1);
    expectError(f, {"csv", 52, "time_s", "time 0.0245 s must be greater than the previous sample's 0.0245 s"});
  }
  {  // NaN, and text, in a sample
    Files f;
    f.replaceLine(40, "0.019,nan,0,0");
    f.write(kSigma, kF1);
    expectError(f, {"csv", 40, "Fz_N", "value 'nan' must be a finite number"});
    Files g;
    g.replaceLine(41, "0.0195,12,-,0");
    g.write(kSigma, kF1);
    expectError(g, {"csv", 41, "stroke_m", "value '-' is not a number"});
    Files h;
    h.replaceLine(42, "0.02,12,0");
    h.write(kSigma, kF1);
    expectError(h, {"csv", 42, "travel_m", "the row has 3 fields, the header (line 1) 4: this column is missing"});
  }
  {  // longer than the drop: 0.3 s of data, a drop of 0.25 s
    Files f;
    f.write(kSigma, kF1);
    std::string text = readFile(f.dir / "c.cfg");
    text.replace(text.find("duration = 0.35"), 15, "duration = 0.25");
    writeFile(f.dir / "c.cfg", text);
    expectError(f, {"csv", 602, "time_s", "beyond the end of case 'drop' (duration 0.25 s)"});
  }
  {  // longer than the drop for the earliest touchdown a fitted t_shift allows
    Files f;
    f.write(kSigma + "\nt_shift = \"fit\"\nt_shift_range = [-0.06, 0.01]", kF1);
    expectError(f, {"csv", 602, "time_s", "0.36 s after touchdown (t - t_shift, t_shift from -0.06 s)"});
  }
  {  // no such file; no header; no rows
    Files f;
    writeFile(f.dir / "c.cfg", calibText("missing.csv", kSigma, kF1));
    expectError(f, {"cfg", 3, "measurement[0].file", "missing.csv': no such file (the path is relative to the calibration file)"});
    Files g;
    g.csv = "# only a comment\n\n";
    g.write(kSigma, kF1);
    expectError(g, {"csv", 0, "header", "no header line"});
    Files h;
    h.csv = "time_s,Fz_N,stroke_m,travel_m\n0,0,0,0\n";
    h.write(kSigma, kF1);
    expectError(h, {"csv", 1, "header", "the file has 1 rows of samples: a measurement needs at least 2"});
  }
}

TEST_CASE("calibrate: bad input is one error line, exit status 2, nothing written", "[calib][cli]") {
  std::string out;
  CHECK(run("calibrate", "--help", out) == 0);
  CHECK(out.find("--threads") != std::string::npos);
  CHECK(run("calibrate", "--version", out) == 0);
  CHECK(out.rfind("calibrate ", 0) == 0);
  Files f;
  f.replaceLine(40, "0.019,nan,0,0");
  f.write(kSigma, kF1);
  const std::string outDir = f.dir / "out";
  const std::vector<std::string> args{q(f.dir / "c.cfg") + " --out " + q(outDir),                       // NaN in the CSV
                                      q(f.dir / "c.cfg") + " --out " + q(outDir) + " --threads -1",    // usage
                                      q(f.dir / "c.cfg") + " --out " + q(outDir) + " --set strut.f1",  // usage
                                      q(f.dir / "none.cfg") + " --out " + q(outDir)};
  for (const auto& a : args) {
    INFO(a);
    CHECK(run("calibrate", a, out) == 2);
    CHECK(out.rfind("error: ", 0) == 0);
    CHECK(std::count(out.begin(), out.end(), '\n') == 1);
    CHECK_FALSE(std::filesystem::exists(outDir));
  }
  CHECK(run("calibrate", args[0], out) == 2);
  CHECK(out == "error: " + f.dir / "drop.csv" + ":40: key 'Fz_N': value 'nan' must be a finite number (measurement 'drop' of " +
                   f.dir / "c.cfg" + ")\n");
}
