#include "sampler/sequences/sets_1d.h"

#include <bit>
#include <cmath>

#include "sampler/point.h"
#include "sampler/sequences/lattice.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/scrambling.h"
#include "sampler/sequences/sobol.h"

namespace nuld {

namespace {
// Divided, not multiplied by 1 / n: a correctly rounded quotient of values
// below n stays below 1.
double stratum(std::size_t k, double jitter, std::size_t n) {
  return (double(k) + jitter) / double(n);
}
}  // namespace

void vanDerCorputSet(std::uint64_t seed, std::span<double> out) {
  const std::size_t n = out.size();
  if (n == 0) return;
  // The digits that tell the N points apart; Owen scrambling draws the rest
  // as one tail per point (owenScramble's distinctDigits).
  const int digits = std::max(1, int(std::bit_width(n - 1)));
  for (std::size_t i = 0; i < n; ++i)
    out[i] = owenScramble(sobolBits(i, 0), seed, digits) * 0x1.0p-32;
  Rng rng(seed, 0x1d5e7);
  shuffle(out, rng);
}

void stratifiedSet1D(std::uint64_t seed, std::span<double> out) {
  const std::size_t n = out.size();
  Rng rng(seed, 0x57a71);
  for (std::size_t k = 0; k < n; ++k) out[k] = stratum(k, rng.uniform(), n);
  shuffle(out, rng);
}

void latticeSet1D(std::uint64_t seed, std::span<double> out, bool baker) {
  const std::size_t n = out.size();
  Rng rng(seed, 0x1a771);
  const double shift = rng.uniform();
  for (std::size_t k = 0; k < n; ++k) {
    const double x = wrapUnit(stratum(k, 0, n) + shift);
    out[k] = baker ? bakerFold(x) : x;
  }
  shuffle(out, rng);
}

}  // namespace nuld
