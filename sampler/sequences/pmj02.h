#pragma once
// Progressive multi-jittered (0,2) sequences (Christensen, Kensler and
// Kilpatrick 2018, "Progressive Multi-Jittered Sample Sequences"), made by
// Pharr's method (JCGT 2019, "Efficient Generation of Points that Satisfy
// Two-Dimensional Elementary Intervals"): every point goes into the
// sub-square the multi-jittered construction gives it, at a finest x strip
// and a finest y strip drawn from those no earlier point's elementary
// interval excludes, which two independent tree walks find.
//
// Every prefix of 2^m points, and every block of 2^m points starting at a
// multiple of 2^m, is a (0,m,2)-net: one point in each elementary interval
// of area 2^-m of every shape 2^-a x 2^-(m-a).

#include <cstdint>
#include <span>
#include <vector>

#include "sampler/point.h"
#include "sampler/sequences/scrambling.h"

namespace nuld {

// The longest sequence pmj02Sequence makes, and the largest set (and index)
// the cached bases of pmj02Set and pmj02Sample serve.
inline constexpr int kPmj02MaxLog2 = 20;
inline constexpr std::size_t kPmj02MaxSet = std::size_t(1) << 16;
// Cached base sequences per length: pmj02Set picks one by its seed.
inline constexpr unsigned kPmj02Bases = 16;

// One pmj02 sequence of 2^log2Count points (log2Count <= kPmj02MaxLog2) from
// `seed`. Progressive: the sequence of 2^k points of a seed is the prefix of
// every longer one of that seed. About 0.4 microseconds a point (25 ms for
// 2^16 on one core).
std::vector<Point2> pmj02Sequence(std::uint64_t seed, int log2Count);

// The first N = out.size() <= kPmj02MaxSet points of a base sequence of
// nextPow2(N) points, randomized from `seed`:
//  - Owen: the base picked by the seed, then nested uniform Owen scrambling
//    of each coordinate (keys from the seed). It maps every elementary
//    interval onto one of the same shape, so every power-of-two prefix (and
//    aligned block) stays a (0,2)-net, and each point is uniform.
//  - Shift: the base picked by the seed under a random digital shift (an
//    XOR per coordinate), which maps elementary intervals the same way.
//  - None: the first base as it is (the same points for every seed).
// The bases (kPmj02Bases per length, made from fixed seeds) are generated on
// first use and kept for the process; any thread may call this. The points
// come in sequence order.
void pmj02Set(std::uint64_t seed, std::span<Point2> out,
              DigitRandomization r = DigitRandomization::Owen);

// Throws std::invalid_argument, naming both, when count > kPmj02MaxSet.
void checkPmj02Count(std::size_t count);

// Coordinate `coordinate` (0: x, 1: y) of point `index` < kPmj02MaxSet of
// the sequence pmj02Set randomizes from `seed`: for a prefix of N points the
// same base and the same flips of the ceil(log2 N) leading digits as
// pmj02Set; with Owen, the digits below are scrambled one by one rather than
// drawn from one hash (the same distribution).
double pmj02Sample(std::uint64_t seed, std::uint64_t index, int coordinate,
                   DigitRandomization r = DigitRandomization::Owen);

}  // namespace nuld
