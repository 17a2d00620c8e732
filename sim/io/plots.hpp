// Pictures of drop tests for every program (simulate --plots, certify --plots, the study report): one
// figure per case, drawn by gnuplot from a data file and a script written beside the picture (both
// kept, so a reader can redraw or restyle them). Six panels: P_y(t), the work diagram P_y(h) (the
// compression and the return stroke in two colours, the peak marked), s(t), the strut's work diagram
// P_a(s), h(t) and the tyre deflection delta(t); every limit given is drawn as a dashed line.
#pragma once

#include <limits>
#include <string>

#include "sim/drop/run.hpp"
#include "sim/io/files.hpp"  // safeFileStem

namespace lg {

// Limits drawn into a case figure (NaN: not drawn).
struct PlotLimits {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  double loadLimit = kNone;     // [N] limit ground load n_g,lim W g
  double loadUltimate = kNone;  // [N] ultimate ground load
  double strokeLimit = kNone;   // [m] S_max of the first strut (its bottoming stop)
  double strokeMargin = kNone;  // [m] the stroke to stay below: S_max - margin
  double tyreLimit = kNone;     // [m] tyre deflection limit
};

struct CaseFigure {
  std::string title;                     // "seed_gear: limit, V = 3.05 m/s, L = 1, W = 4050 kg"
  const CaseResult* run = nullptr;       // recorded samples
  const CaseResult* baseline = nullptr;  // optional: a second run drawn in grey ("baseline")
  std::string runLabel = "compression", baselineLabel = "baseline";
  PlotLimits limits;
  std::string strut, tyre;  // the elements drawn when the scene has several (their columns "s_<strut>", ...)
  // Draws the scene's first strut and first tyre.
  void drawElementsOf(const Scene& scene);
};

// True when gnuplot can be run (looked up once per process).
bool haveGnuplot();

// The limits of a case for the picture: the scene's first strut's S_max and first tyre's delta_max.
PlotLimits sceneLimits(const Scene& scene);

// Writes DIR/STEM.dat (DIR/STEM_baseline.dat), DIR/STEM.gp and, when 'run', DIR/STEM.png. Returns
// false with the reason when gnuplot is missing or fails (data and script are written regardless).
// STEM must be a safe file stem (safeFileStem). Throws std::runtime_error if a file cannot be written.
bool drawCaseFigure(const CaseFigure& f, const std::string& dir, const std::string& stem, bool run, std::string* why);

// Runs gnuplot on DIR/STEM.gp in DIR (STEM a safe file stem); false with the reason when gnuplot is
// missing or fails (its messages in DIR/STEM.gnuplot.log).
bool runGnuplot(const std::string& dir, const std::string& stem, std::string* why);

// A gnuplot single-quoted string (quotes doubled), for titles and file names in scripts.
std::string gnuplotQuoted(const std::string& s);

}  // namespace lg
