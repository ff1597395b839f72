#include "sampler/sequences/scrambling.h"

#include <algorithm>
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

// The image of `digit` under a uniformly random permutation of {0..base-1}
// chosen by `key`: the permutation rng.h's Fisher-Yates shuffle makes with
// Rng(key), found without making it. The shuffle's step i (i = base down to
// 2, draw number base - i + 1) swaps positions i - 1 and j_i <= i - 1, so
// position `digit` is final after step digit + 1 and no later step touches
// it; tracing where its value stood before each step, from that step back
// to the first, ends at the value's start, which is its value (the shuffle
// starts from the identity). The generator is counter-based, so each step's
// draw is made directly: base - digit draws instead of base - 1, and no
// array (a Halton coordinate permutes a digit per level, at bases up to the
// dimension's prime).
std::uint32_t permuteDigit(std::uint32_t digit, std::uint32_t base, std::uint64_t key) {
  constexpr std::uint32_t kMaxBase = 1024;
  if (base > kMaxBase) throw std::invalid_argument("radicalInverse: base too large to scramble");
  const Rng rng(key);
  std::uint32_t p = digit;
  for (std::uint32_t i = std::max(2u, digit + 1); i <= base; ++i) {
    Rng step = rng;
    step.advance(base - i);
    const std::uint32_t j = step.uniformInt(i);
    if (p == i - 1) {
      p = j;
    } else if (p == j) {
      p = i - 1;
    }
  }
  return p;
}

namespace {

// The digits radicalInverse scrambles before the next is below double
// precision: ceil(54 / log2 base), for the bases Halton's primes reach.
int scrambledDigits(std::uint32_t base) {
  static const std::array<int, 1025> table = [] {
    std::array<int, 1025> t{};
    for (std::uint32_t b = 2; b < t.size(); ++b)
      t[b] = static_cast<int>(std::ceil(54.0 / std::log2(double(b))));
    return t;
  }();
  return base < table.size() ? table[base]
                             : static_cast<int>(std::ceil(54.0 / std::log2(double(base))));
}

}  // namespace

double radicalInverse(std::uint64_t index, std::uint32_t base, DigitRandomization r,
                      std::uint64_t seed, int distinctDigits) {
  if (base < 2) throw std::invalid_argument("radicalInverse: base must be at least 2");
  const double invBase = 1.0 / base;
  // Enough digits that the next one is below double precision.
  const int digits = r == DigitRandomization::None ? 64 : scrambledDigits(base);
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
