// The outputs of `certify`: compliance.json (the verdict for programs) and compliance.md (a table a
// reviewer reads in a minute), with one picture per case (sim/io/plots.hpp) and the limits drawn.
#pragma once

#include <string>
#include <vector>

#include "sim/drop/certification.hpp"
#include "sim/io/plots.hpp"

namespace lg {

std::string complianceJson(const Compliance& c);
// 'pictures': markdown lines with the case pictures (or a sentence why there are none).
std::string complianceMarkdown(const Compliance& c, const std::string& pictures);
// A one-line verdict per case and the whole unit, for the terminal.
std::string complianceSummary(const Compliance& c);

// The strut at rest (compliance.servicing): DIR/static_curve.csv (s, p_1, P_a, r) and
// DIR/servicing_chart.csv (extension, then the gauge pressure and its band at each ambient temperature),
// units in the headers; and the servicing chart's picture (DIR/STEM.dat, STEM.gp; gnuplot when 'run').
std::string staticCurveCsv(const ServicingCurve& c);
std::string servicingChartCsv(const ServicingCurve& c);
bool drawServicingChart(const ServicingCurve& c, const std::string& dir, const std::string& stem, bool run, std::string* why);

// The limits of a case drawn in its picture: limit and ultimate load for its W, stroke and tyre limits.
PlotLimits compliancePlotLimits(const Scene& scene, const Certification& spec, const CaseVerdict& v);

}  // namespace lg
