#pragma once
// Jittered (stratified) sampling, as pbrt-v4's StratifiedSampler and
// Mitsuba's stratified sampler make it: the square cut into cells, one
// uniform point per cell. The jitter is the whole randomization, so there is
// no scrambling to choose.

#include <cstddef>
#include <cstdint>
#include <span>

#include "sampler/point.h"

namespace nuld {

// The side m of the grid of a set of n points: the smallest m with m * m >= n.
std::uint32_t stratifiedGridSide(std::size_t n);

// N = out.size() jittered points from `seed`. A square N = n * n: the n x n
// grid, one uniform point per cell. Any other N: the m x m grid of
// stratifiedGridSide(N), N distinct cells drawn uniformly without
// replacement, one uniform point in each: no two points share a cell, and
// each point is still uniform on [0, 1)^2 (a uniformly chosen cell, a
// uniform point in it), so every estimate stays unbiased. The points come in
// a random order (the cells are drawn by a partial Fisher-Yates shuffle), so
// a renderer that pairs dimensions by index pairs them at random.
void stratifiedSet(std::uint64_t seed, std::span<Point2> out);

}  // namespace nuld
