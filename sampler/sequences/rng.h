#pragma once
// Counter-based random numbers: every value is a pure function of
// (seed, stream, index), so any sample can be regenerated independently,
// in any order and on any thread, and runs are reproducible by construction.

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>

namespace nuld {

// The seed when none is given, the same for every command and Python entry
// point (docs/usage.md, "Seeds"): sets a bank or a study made then serve a
// later render from the set cache, and a run without --seed is the run
// with --seed 1.
inline constexpr std::uint64_t kDefaultSeed = 1;

// The splitmix64 finalizer: a bijective 64-bit mixer with full avalanche.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z ^= z >> 30;
  z *= 0xbf58476d1ce4e5b9ull;
  z ^= z >> 27;
  z *= 0x94d049bb133111ebull;
  z ^= z >> 31;
  return z;
}

constexpr std::uint64_t hashCombine(std::uint64_t a, std::uint64_t b) {
  return mix64(a ^ (mix64(b) + 0x9e3779b97f4a7c15ull + (a << 6) + (a >> 2)));
}

constexpr std::uint64_t hash3(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  return hashCombine(hashCombine(mix64(a), b), c);
}

// Maps 64 random bits to a double in [0, 1) with 53 bits of precision.
constexpr double toUnitDouble(std::uint64_t bits) {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

// A sequential stream over a counter-based generator: value k (from 1) of
// stream (seed, stream) is mix64(key + k * 0x9e3779b97f4a7c15), the key
// being hashCombine(mix64(seed), stream). Cheap to copy and to skip ahead.
class Rng {
 public:
  explicit Rng(std::uint64_t seed = 0, std::uint64_t stream = 0)
      : key_(hashCombine(mix64(seed), stream)) {}

  std::uint64_t nextBits() { return mix64(key_ + 0x9e3779b97f4a7c15ull * ++counter_); }
  std::uint32_t nextU32() { return static_cast<std::uint32_t>(nextBits() >> 32); }
  double uniform() { return toUnitDouble(nextBits()); }
  // Uniform integer in [0, n) by Lemire's multiply-shift (bias < 2^-32 n).
  std::uint32_t uniformInt(std::uint32_t n) {
    return static_cast<std::uint32_t>((static_cast<std::uint64_t>(nextU32()) * n) >> 32);
  }
  void advance(std::uint64_t k) { counter_ += k; }

 private:
  std::uint64_t key_;
  std::uint64_t counter_ = 0;
};

// Fisher-Yates: a uniformly random permutation of `v`, one draw per swap.
// (The renderer's per-pixel shuffle, shufflePoints in renderer/padding.h,
// spends one 64-bit draw on two swaps: it runs for every pixel and pair.)
template <class T>
void shuffle(std::span<T> v, Rng &rng) {
  for (std::size_t i = v.size(); i > 1; --i)
    std::swap(v[i - 1], v[rng.uniformInt(std::uint32_t(i))]);
}

// Independent uniform samples addressed by (seed, index, dimension).
inline double independentSample(std::uint64_t seed, std::uint64_t index, std::uint32_t dim) {
  return toUnitDouble(hash3(seed, index, dim));
}

}  // namespace nuld
