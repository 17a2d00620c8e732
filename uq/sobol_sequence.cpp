// Shifted Sobol points (sobol_sequence.hpp).
#include "uq/sobol_sequence.hpp"

#include <stdexcept>
#include <string>

#include <boost/random/sobol.hpp>

#include "uq/random.hpp"

namespace lg::uq {

std::vector<double> shiftedSobol(std::size_t n, std::size_t dim, std::uint64_t seed) {
  if (dim == 0 || dim > kSobolMaxDimension)
    throw std::invalid_argument("Sobol sequence: dimension " + std::to_string(dim) + " must be in [1, " +
                                std::to_string(kSobolMaxDimension) + "]");
  std::vector<std::uint32_t> shift(dim);
  Rng rng(seed);
  for (auto& s : shift) s = static_cast<std::uint32_t>(rng.bits() >> 32);
  boost::random::sobol_engine<std::uint32_t, 32> engine(dim);
  std::vector<double> out(n * dim);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < dim; ++k) {
      const std::uint32_t raw = i == 0 ? 0u : engine();  // Boost starts after the zero point
      out[i * dim + k] = (static_cast<double>(raw ^ shift[k]) + 0.5) * 0x1.0p-32;
    }
  return out;
}

}  // namespace lg::uq
