#pragma once
// Nested uniform Owen scrambling of one coordinate of a whole set at once.
// owenScramble (scrambling.h) walks the scrambling tree from the root for
// every point; the points of a set share their short prefixes (level l has at
// most 2^l of them), so here each prefix's flips are computed once, in a
// table by level, and every point then adds its own tail. Owen-scrambled
// Sobol sets (sequence.cpp) and pmj02 sets (pmj02.cpp) both go through it.

#include <cstdint>
#include <span>

#include "sampler/point.h"

namespace nuld {

// Sets coordinate `coordinate` of out[i] to bits[i] scrambled by the tree of
// `seed` (OwenTree), as owenScramble(bits[i], seed, d) * 2^-32 would: the
// points must be told apart by their d < 32 leading digits (as the first
// n <= 2^d points of a (0,2)-sequence's coordinate are), so that the digits
// below d are one independent tail per point. bits and out have one size.
void owenScrambleSet(std::uint64_t seed, int d, std::span<const std::uint32_t> bits,
                     std::span<Point2> out, double Point2::*coordinate);

}  // namespace nuld
