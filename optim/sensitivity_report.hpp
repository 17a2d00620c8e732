// The outputs of a sensitivity study (sensitivity.hpp), all written by rank 0 only, atomically, and
// free of timings and rank or thread counts, so that a run on any number of ranks and threads writes
// the same bytes:
//   report.md             what was run, the failed runs, and per method and metric the tables and the
//                         pictures (plots/: tornado_<metric>, morris_<metric>, sobol_<metric>; gnuplot
//                         data and scripts kept beside them)
//   samples_<method>.csv  every run: its design (variables with units) and every output (metric@case
//                         with units), and why it failed
//   indices_<method>.csv  every index: elasticities; mu, mu*, sigma with the interval on mu*; S1 and ST
//                         with their intervals and warnings
//   convergence_sobol.csv S1 and ST against N (N/8, N/4, N/2, N)
//   indices.json          the same indices, the settings and the failed runs
#pragma once

#include <string>
#include <vector>

#include "optim/sensitivity.hpp"
#include "sim/io/provenance.hpp"

namespace lg::optim {

// The warnings of the Sobol indices: an interval wider than the index it bounds, blocks dropped.
std::vector<std::string> sobolWarnings(const Study& s, const SensitivityResult& r);

std::string sensitivityJson(const Study& s, const SensitivityResult& r);
std::string samplesCsv(const Study& s, const SensitivityResult& r, const std::string& method);
std::string indicesCsv(const Study& s, const SensitivityResult& r, const std::string& method);
std::string convergenceCsv(const Study& s, const SensitivityResult& r);
// note: empty when the pictures were made, otherwise why not (said in the report instead of them).
std::string sensitivityMarkdown(const Study& s, const SensitivityResult& r, const std::string& note);
// The parts of a local derivative's one-sidedness note (its reasons joined by "; ") that hold for the
// parameter 'path': the lift plateau's is one-sided in the lift ratio alone, the others in every one.
std::string oneSidedFor(const std::string& note, const std::string& path);

struct SensitivityFiles {
  std::vector<std::string> written;   // file names relative to the output directory
  bool pictures = false;              // gnuplot made the pictures
  std::vector<std::string> warnings;  // for the terminal
};

// Creates 'dir' and writes every output; plots = false skips gnuplot (data and scripts still written).
// Throws std::runtime_error when a file cannot be written.
// 'provenance' (optional) heads indices.json and report.md (sim/io/provenance.hpp).
SensitivityFiles writeSensitivity(const Study& s, const SensitivityResult& r, const std::string& dir, bool plots,
                                  const Provenance* provenance = nullptr);

}  // namespace lg::optim
