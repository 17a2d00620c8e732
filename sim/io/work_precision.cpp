// Work-precision output (sim/io/work_precision.hpp).
#include "sim/io/work_precision.hpp"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <sstream>

#include "sim/io/files.hpp"
#include "sim/io/plots.hpp"

namespace lg {

void writeWorkPrecisionCsv(const std::vector<WorkPrecisionPoint>& points, const std::string& path) {
  std::ostringstream f;
  f << "case,integrator,tolerance,steps,rhs_evaluations,time_per_drop_s,error_peak_load,error_t_peak,error_stroke,"
       "error_travel,error_tyre_deflection,error_efficiency,error_strut_force,error_drag_peak,error_max,ok\n";
  char buf[512];
  for (const auto& p : points) {
    const MetricErrors& e = p.errors;
    std::snprintf(buf, sizeof buf, "%s,%s,%.3g,%ld,%ld,%.6e,%.3e,%.3e,%.3e,%.3e,%.3e,%.3e,%.3e,%.3e,%.3e,%d\n",
                  p.caseName.c_str(), p.integrator.c_str(), p.tolerance, p.steps, p.rhsEvaluations, p.timePerDrop,
                  e.peakLoad, e.tPeak, e.stroke, e.travel, e.tyreDeflection, e.efficiency, e.strutForce, e.dragPeak,
                  e.max(), p.ok ? 1 : 0);
    f << buf;
  }
  writeFileAtomic(path, f.str());
}

void printWorkPrecisionTable(const std::vector<WorkPrecisionPoint>& points, std::FILE* out) {
  std::fprintf(out, "%-10s %-9s %9s %6s %6s %10s %10s %10s %10s %10s\n", "case", "solver", "tol/step", "steps", "rhs",
               "time[ms]", "peak err", "stroke err", "travel err", "max err");
  for (const auto& p : points) {
    const MetricErrors& e = p.errors;
    std::fprintf(out, "%-10s %-9s %9.0e %6ld %6ld %10.3f %10.2e %10.2e %10.2e %10.2e%s\n", p.caseName.c_str(),
                 p.integrator.c_str(), p.tolerance, p.steps, p.rhsEvaluations, 1e3 * p.timePerDrop, e.peakLoad, e.stroke,
                 e.travel, e.max(), p.ok ? "" : ("  FAILED: " + p.message).c_str());
  }
}

bool writeWorkPrecisionPlots(const Scene& scene, const std::vector<WorkPrecisionPoint>& points,
                             const std::string& outDir, std::string* why) {
  std::vector<std::string> cases;
  for (const auto& p : points)
    if (std::find(cases.begin(), cases.end(), p.caseName) == cases.end()) cases.push_back(p.caseName);
  bool drawn = haveGnuplot();
  if (!drawn && why) *why = "gnuplot is not installed (scripts/setup.sh installs gnuplot-nox)";
  for (const auto& c : cases) {
    const std::string stem = "work_precision_" + safeFileStem(c);
    // One data block per integrator: time [ms], then the errors [%] of peak load, stroke, travel.
    std::map<std::string, std::string> blocks;
    std::vector<std::string> order;
    for (const auto& p : points) {
      if (p.caseName != c || !p.ok) continue;
      if (!blocks.count(p.integrator)) order.push_back(p.integrator);
      char line[160];
      const double floor = 1e-10;  // [%] zero errors drawn at the bottom of the log scale
      std::snprintf(line, sizeof line, "%.6g %.4g %.4g %.4g\n", 1e3 * p.timePerDrop,
                    std::max(100 * p.errors.peakLoad, floor), std::max(100 * p.errors.stroke, floor),
                    std::max(100 * p.errors.travel, floor));
      blocks[p.integrator] += line;
    }
    std::ostringstream d;
    for (const auto& k : order) d << "# " << k << "\n" << blocks[k] << "\n\n";
    writeFileAtomic(outDir + "/" + stem + ".dat", d.str());
    std::ostringstream g;
    g << "set terminal pngcairo size 1500,500 noenhanced\nset output " << gnuplotQuoted(stem + ".png")
      << "\nset multiplot layout 1,3 title "
      << gnuplotQuoted(scene.name + ", case " + c + ": error against time per drop (one core)") << "\n"
      << "set logscale xy\nset format y '%g'\nset format x '%g'\nset grid\nset key top right\n"
         "set xlabel 'time per drop [ms]'\n";
    const char* titles[] = {"peak load", "max stroke", "max travel h"};
    for (int col = 0; col < 3; ++col) {
      // One legend, in the first panel's top right corner (slow and inaccurate: no setting lies there).
      if (col == 1) g << "unset key\n";
      g << "set ylabel 'relative error of the " << titles[col] << " [%]'\nset title '" << titles[col] << "'\nplot ";
      for (size_t i = 0; i < order.size(); ++i)
        g << (i ? ", " : "") << gnuplotQuoted(stem + ".dat") << " index " << i << " using 1:" << (col + 2)
          << " with linespoints title " << gnuplotQuoted(order[i]);
      g << "\n";
    }
    g << "unset multiplot\n";
    writeFileAtomic(outDir + "/" + stem + ".gp", g.str());
    if (drawn && !runGnuplot(outDir, stem, why)) drawn = false;
  }
  return drawn;
}

}  // namespace lg
