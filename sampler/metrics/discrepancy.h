#pragma once
// Discrepancy measures of 2D point sets. All return the plain (not squared)
// discrepancy. The uniform measures are closed forms; the non-uniform ones
// take box masses from a target.

#include <span>

#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

// L2-star discrepancy by Warnock's formula, O(N^2).
double l2StarDiscrepancy(std::span<const Point2> points);

// L2 "all-corners, sampled-diagonal" discrepancy: the root of the average,
// over the 4 corners c and uniform y, of the squared local discrepancy of the
// box spanned by c and y (closed form of DESIGN.md §3), O(N^2).
double l2asd(std::span<const Point2> points);

// Exact star discrepancy sup over anchored boxes [0,a] x [0,b] of
// |count/N - mu|, open and closed boxes alike. With `target` null mu is the
// area. O(N^2) mass evaluations, parallel over the critical a values.
double starDiscrepancy(std::span<const Point2> points, const Target *target = nullptr);

// Non-uniform L2-star (anchored boxes) and L2asd (all 4 corners) against a
// target, integrated exactly against the bilinear interpolant of the target's
// CDF on a grid: the target's own cells for grid targets (then exact), else a
// res x res grid (exact for uniform targets, O(1/res^2) error otherwise).
double nonuniformL2Star(std::span<const Point2> points, const Target &target, int res = 256);
double nonuniformL2asd(std::span<const Point2> points, const Target &target, int res = 256);

}  // namespace nuld
