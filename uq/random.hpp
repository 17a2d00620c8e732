// Seeded random numbers that give the same bits on every platform: std::mt19937_64 (its output
// sequence is fixed by the C++ standard) with our own integer and real maps (the standard
// distributions are not, so they are never used where results must be reproducible).
#pragma once

#include <cstddef>
#include <cstdint>
#include <random>

namespace lg::uq {

// SplitMix64 of (seed, stream): independent seeds for the methods of one run (the Sobol shift, the
// Morris trajectories, each bootstrap) from the one seed a user gives.
std::uint64_t streamSeed(std::uint64_t seed, std::uint64_t stream);

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : g_(seed) {}
  std::uint64_t bits() { return g_(); }
  // Uniform integer in [0, n), n >= 1 (rejection: no modulo bias).
  std::size_t below(std::size_t n);
  // Uniform real in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(g_() >> 11) * 0x1.0p-53; }

 private:
  std::mt19937_64 g_;
};

}  // namespace lg::uq
