#pragma once
// Randomizations of digital sequences.
//
// Base 2 (Sobol) works on the 32-bit integer of a coordinate:
//  - nested uniform Owen scrambling: digit i (from the most significant) is
//    flipped by a hash of (seed, i, the i more significant digits), so every
//    elementary interval is permuted independently; (t,m,s)-nets stay nets.
//  - random digital shift: XOR with one random 32-bit word per dimension.
// Any base (Halton): the same two ideas on base-b digits, Owen scrambling with
// a hash-seeded random permutation per digit prefix.
// Cranley-Patterson rotation (a toroidal shift) applies to any point.

#include <array>
#include <cstdint>

#include "sampler/point.h"
#include "sampler/sequences/rng.h"

namespace nuld {

// Base-2 nested uniform scrambling as a random binary tree keyed by a seed:
// digit `length` (0 = most significant) under the `length` leading digits
// `prefix` is flipped by an independent random bit. The 63 nodes of the top
// kTopLevels levels take the bits of one hash; deeper nodes one hash each.
// owenScramble walks it for one coordinate; generateSet walks it once per
// shared prefix for a whole Sobol set. Both must draw the same flips, so both
// use this.
class OwenTree {
 public:
  static constexpr int kTopLevels = 6;  // 2^6 - 1 = 63 nodes: one 64-bit hash

  explicit OwenTree(std::uint64_t seed)
      : key_(mix64(seed ^ 0x5851f42d4c957f2dull)), top_(mix64(key_ ^ 0x0f1e2d3c4b5a6978ull)) {}

  // Tagged with the length so prefixes of different lengths never share a hash.
  std::uint64_t prefixHash(std::uint64_t prefix, int length) const {
    return mix64(key_ + 0x9e3779b97f4a7c15ull * ((prefix << 6) | std::uint64_t(length)));
  }
  // The flip of digit `length`, in place in a 32-bit word.
  std::uint32_t digitFlip(std::uint64_t prefix, int length) const {
    const std::uint64_t bits = length < kTopLevels ? top_ >> ((1u << length) - 1 + prefix)
                                                   : prefixHash(prefix, length) >> 63;
    return static_cast<std::uint32_t>(bits & 1) << (31 - length);
  }
  // Independent uniform flips of digit `length` and every digit below it
  // (length < 32): they sit under a prefix no other point of the set shares.
  // Sibling prefixes share one hash, a 32-bit half each.
  std::uint32_t tailFlips(std::uint64_t prefix, int length) const {
    return siblingTailFlips(prefix >> 1, length)[prefix & 1];
  }
  // tailFlips of the siblings 2q and 2q + 1 from their one hash.
  std::array<std::uint32_t, 2> siblingTailFlips(std::uint64_t q, int length) const {
    const std::uint64_t h = prefixHash(q, length);
    return {static_cast<std::uint32_t>(h >> 32) >> length, static_cast<std::uint32_t>(h) >> length};
  }

 private:
  std::uint64_t key_, top_;
};

// `distinctDigits` d: when the points being scrambled together are told
// apart by their d leading digits (the first N <= 2^d points of a Sobol
// dimension, or N <= b^d Halton indices), every digit below d sits under a
// prefix no other point shares, so its scrambled value is an independent
// uniform digit. Those digits are then drawn from one hash of the d-digit
// prefix instead of one hash each: the joint distribution of the N points is
// unchanged and scrambling costs d + 1 hashes instead of 32 (or 54 / log2 b).
// The default scrambles every digit separately.
std::uint32_t owenScramble(std::uint32_t bits, std::uint64_t seed, int distinctDigits = 32);
std::uint32_t digitalShift(std::uint32_t bits, std::uint64_t seed);
double cranleyPatterson(double x, std::uint64_t seed);
// A point under the toroidal shift of `seed`: x by the seed's offset, y by
// that of ~seed (the two coordinates are shifted independently).
inline Point2 cranleyPatterson(Point2 p, std::uint64_t seed) {
  return {cranleyPatterson(p.x, seed), cranleyPatterson(p.y, ~seed)};
}

enum class DigitRandomization { None, Owen, Shift };

// The image of `digit` under the uniformly random permutation of
// {0..base-1} that shuffle() in rng.h makes with Rng(key): the permutation
// the Owen-scrambled radical inverse applies to a digit under one prefix,
// found without making it. Throws std::invalid_argument for base > 1024.
std::uint32_t permuteDigit(std::uint32_t digit, std::uint32_t base, std::uint64_t key);

// Radical inverse of `index` in `base` with its digits randomized. With a
// randomization, all digits down to double precision are randomized, not only
// the non-zero ones, so the result is uniform on [0, 1).
double radicalInverse(std::uint64_t index, std::uint32_t base, DigitRandomization r,
                      std::uint64_t seed, int distinctDigits = 64);

}  // namespace nuld
