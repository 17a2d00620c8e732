// Percentile bootstrap intervals shared by the Sobol and Morris estimators: the same seeded resamples
// for every output of a run, the interval from the sorted replicates by linear interpolation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lg::uq {

struct Interval {
  double lo = 0, hi = 0;
  double width() const { return hi - lo; }
};

struct BootstrapOptions {
  int resamples = 100;       // [-] number of bootstrap replicates (0: no intervals)
  double confidence = 0.95;  // [-] central percentile interval
  std::uint64_t seed = 1;
};

// 'resamples' lists of n indices drawn with replacement from [0, n), seeded.
std::vector<std::vector<std::size_t>> bootstrapSamples(std::size_t n, const BootstrapOptions& o);

// The central 'confidence' interval of the replicates (sorted here; empty: [NaN, NaN]).
Interval percentileInterval(std::vector<double> replicates, double confidence);

}  // namespace lg::uq
