// A digitally shifted Sobol sequence in [0, 1)^dim from Boost.Random's sobol_engine (Joe and Kuo's
// direction numbers, up to 3667 dimensions), 32 bits per coordinate.
//
// The zero point comes first, then Boost's points in Gray-code order, so the first 2^m points are a
// (t, m, dim)-net. Each coordinate's 32 bits are XOR-ed with a seeded random mask (a random digital
// shift: the net property is kept, the estimates become unbiased and the seed gives independent
// replicates), and each value is the centre of its 2^-32 cell, so never exactly 0 or 1.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lg::uq {

constexpr std::size_t kSobolMaxDimension = 3667;

// n points of dimension dim (row-major: point i is [i*dim, (i+1)*dim)); throws std::invalid_argument
// for dim = 0 or dim > kSobolMaxDimension.
std::vector<double> shiftedSobol(std::size_t n, std::size_t dim, std::uint64_t seed);

}  // namespace lg::uq
