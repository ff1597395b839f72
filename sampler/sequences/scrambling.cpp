#include "sampler/sequences/scrambling.h"

#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "sampler/point.h"
#include "sampler/sequences/rng.h"

namespace nuld {

std::uint32_t owenScramble(std::uint32_t bits, std::uint64_t seed, int distinctDigits) {
  const OwenTree tree(seed);
  const auto prefix = [bits](int i) -> std::uint64_t { return i == 0 ? 0 : bits >> (32 - i); };
  const int exact = distinctDigits < 0 ? 0 : (distinctDigits > 32 ? 32 : distinctDigits);
  std::uint32_t flips = 0;
  for (int i = 0; i < exact; ++i) flips |= tree.digitFlip(prefix(i), i);
  if (exact < 32) flips |= tree.tailFlips(prefix(exact), exact);
  return bits ^ flips;
}

std::uint32_t digitalShift(std::uint32_t bits, std::uint64_t seed) {
  return bits ^ static_cast<std::uint32_t>(mix64(seed ^ 0x2545f4914f6cdd1dull) >> 32);
}

double cranleyPatterson(double x, std::uint64_t seed) {
  return wrapUnit(x + toUnitDouble(mix64(seed ^ 0x9e3779b97f4a7c15ull)));
}

namespace {

// The image of `digit` under a uniformly random permutation of {0..base-1}
// chosen by `key` (Fisher-Yates driven by the counter-based generator).
std::uint32_t permuteDigit(std::uint32_t digit, std::uint32_t base, std::uint64_t key) {
  constexpr std::uint32_t kMaxBase = 1024;
  if (base > kMaxBase) throw std::invalid_argument("radicalInverse: base too large to scramble");
  std::array<std::uint16_t, kMaxBase> perm;
  std::iota(perm.begin(), perm.begin() + base, 0);
  Rng rng(key);
  shuffle(std::span(perm.data(), base), rng);
  return perm[digit];
}

}  // namespace

double radicalInverse(std::uint64_t index, std::uint32_t base, DigitRandomization r,
                      std::uint64_t seed, int distinctDigits) {
  if (base < 2) throw std::invalid_argument("radicalInverse: base must be at least 2");
  const double invBase = 1.0 / base;
  // Enough digits that the next one is below double precision.
  const int digits = r == DigitRandomization::None
                         ? 64
                         : static_cast<int>(std::ceil(54.0 / std::log2(double(base))));
  double scale = invBase, result = 0;
  std::uint64_t prefixKey = mix64(seed);
  for (int i = 0; i < digits; ++i) {
    if (r == DigitRandomization::None && index == 0) break;
    if (r == DigitRandomization::Owen && i >= distinctDigits) {
      // A prefix unique to this point: the rest is a uniform tail on [0, b^-i).
      result += scale * base * toUnitDouble(mix64(prefixKey ^ 0x7a11ull));
      break;
    }
    const auto digit = static_cast<std::uint32_t>(index % base);
    index /= base;
    std::uint32_t out = digit;
    if (r == DigitRandomization::Owen) {
      out = permuteDigit(digit, base, prefixKey);
      prefixKey = hashCombine(prefixKey, digit + 1);
    } else if (r == DigitRandomization::Shift) {
      const auto shift = static_cast<std::uint32_t>(hash3(seed, i, 0x51u) % base);
      out = (digit + shift) % base;
    }
    result += out * scale;
    scale *= invBase;
  }
  return result < 1.0 ? result : std::nextafter(1.0, 0.0);
}

}  // namespace nuld
