// Synthetic drop-test measurements: a scene's drop sampled like a rig records it (a fixed rate, a clock
// whose zero is not the touchdown, Gaussian noise of a stated sigma per channel from a fixed seed),
// written as a measurement CSV for `calibrate`. The simulation is the calibration's own
// (residuals.hpp: rows on the dense output, free fall before touchdown), so noise-free data at the
// true values are the model's values to the last bit. Used by the synthetic_drop tool and the tests.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "sim/io/scene.hpp"

namespace lg::calib {

struct SyntheticChannel {
  std::string name;       // history column ("P_y", "s", "h", ...)
  std::string csvColumn;  // its CSV header ("Fz_N")
  double sigma = 0;       // [unit] standard deviation of the added noise (0: none)
};

struct SyntheticSpec {
  DropCase dropCase;                       // the drop (a scene case or a new one)
  std::vector<SyntheticChannel> channels;
  std::string timeColumn = "time_s";
  double rate = 2000;                      // [Hz] samples per second
  double start = 0;                        // [s] the first sample, in the rig's clock
  double end = 0.5;                        // [s] the last sample at most, in the rig's clock
  double touchdown = 0;                    // [s] the touchdown in the rig's clock (the t_shift to find)
  std::uint64_t seed = 1;                  // of the noise
  int digits = 17;                         // significant digits written (17: exact; a rig writes fewer)
};

// The rows t_k = start + k / rate up to end, the channels from a drop of 'scene' and noise added; the
// CSV text with a header. Throws std::invalid_argument for a bad spec, std::runtime_error when the drop fails.
std::string syntheticCsv(const Scene& scene, const SyntheticSpec& spec);

// Standard normal numbers from a seed: Box-Muller on the 53-bit uniforms of std::mt19937_64 (both
// fully specified by the C++ standard, so the same seed gives the same numbers everywhere).
class GaussianNoise {
 public:
  explicit GaussianNoise(std::uint64_t seed) : engine_(seed) {}
  double next();

 private:
  double uniform();  // in (0, 1]
  std::mt19937_64 engine_;
  bool haveSpare_ = false;
  double spare_ = 0;
};

}  // namespace lg::calib
