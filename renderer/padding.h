#pragma once
// Padding (Kollig & Keller 2002): the renderer asks every domain of a pixel
// (renderer/sample_layout.h) for its N samples separately, and sample i
// combines sample i of each domain. Pairs cut from the same net (every pair of the sobol and halton
// backends is a scrambled copy of dimensions 0 and 1; optimized sets come
// from one bank) share its index order: scrambling each copy independently
// still ties point i of one pair to point i of another by a fixed bijection,
// so the N combined samples lie on a lower-dimensional pattern whose error
// stops falling with N (tools/experiments/implementation_notes.md). Each
// (pixel, domain) therefore deals its samples out in a random order of its
// own: domains are matched at random, and every domain keeps its
// stratification.

#include <span>

#include "sampler/point.h"
#include "sampler/sequences/rng.h"

namespace nuld {

// A uniformly random permutation of `points` keyed by `seed` (Fisher-Yates;
// each 64-bit draw serves two swaps, by Lemire's multiply-shift on 32 bits).
template <class T>
void shuffleSamples(std::span<T> points, std::uint64_t seed) {
  Rng rng(seed, 0x5eed5bu);
  const auto below = [](std::uint64_t bits32, std::size_t n) {
    return std::size_t((bits32 * n) >> 32);
  };
  for (std::size_t i = points.size(); i > 1; i -= 2) {
    const std::uint64_t bits = rng.nextBits();
    std::swap(points[i - 1], points[below(bits & 0xffffffffu, i)]);
    if (i > 2) std::swap(points[i - 2], points[below(bits >> 32, i - 1)]);
  }
}

// A 2D domain's points and a 1D domain's numbers.
inline void shufflePoints(std::span<Point2> points, std::uint64_t seed) {
  shuffleSamples(points, seed);
}
inline void shufflePoints(std::span<double> numbers, std::uint64_t seed) {
  shuffleSamples(numbers, seed);
}

}  // namespace nuld
