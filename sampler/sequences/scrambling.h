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

#include <cstdint>

namespace nuld {

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

enum class DigitRandomization { None, Owen, Shift };

// Radical inverse of `index` in `base` with its digits randomized. With a
// randomization, all digits down to double precision are randomized, not only
// the non-zero ones, so the result is uniform on [0, 1).
double radicalInverse(std::uint64_t index, std::uint32_t base, DigitRandomization r,
                      std::uint64_t seed, int distinctDigits = 64);

}  // namespace nuld
