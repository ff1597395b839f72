#pragma once
// Discrepancy measures of 2D point sets. All return the plain (not squared)
// discrepancy. The uniform measures are closed forms; the non-uniform ones
// take box masses from a target.

#include <span>
#include <string>

#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

// L2-star discrepancy by Warnock's formula, O(N^2).
double l2StarDiscrepancy(std::span<const Point2> points);

// L2 "all-corners, sampled-diagonal" discrepancy: the root of the average,
// over the 4 corners c and uniform y, of the squared local discrepancy of the
// box spanned by c and y (closed form in docs/architecture.md, "Metrics"), O(N^2).
double l2asd(std::span<const Point2> points);

// Periodic L2 discrepancy: the root mean square, over all boxes of the unit
// torus (in each coordinate the interval from a_k up to b_k, wrapping past 1
// when b_k < a_k; a and b uniform), of count / N - volume. A closed form,
// O(N^2):
//   D^2 = (1/N^2) sum_i sum_j prod_k (1/2 - d_k (1 - d_k)) - (1/3)^2,
//   d_k = frac(x_ik - x_jk).
// Any toroidal shift of all points leaves it unchanged, so a set optimized
// for it keeps its quality under Cranley-Patterson randomization. (Hickernell's
// wrap-around discrepancy, scipy's 'WD', sums this over every projection of
// the coordinates: WD^2 = D_x^2 + D_y^2 + D^2 in 2D.) Points are read modulo 1.
double periodicL2(std::span<const Point2> points);
// D^2 and, unless `grad` is empty, dD^2/dx_i into grad (size N):
//   (2/N^2) sum_j (2 d_k - 1) prod_{l != k} (1/2 - d_l (1 - d_l)).
double periodicL2Squared(std::span<const Point2> points, std::span<Point2> grad = {});

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

// The metrics by the names `nuld eval` and the Python module use, against
// `target` (closed forms when it is uniform, the grid of `res` otherwise):
//   l2star, l2asd, dstar, l2 (the grid L2asd even for a uniform target) and
//   l2per (uniform targets only).
// Throws std::invalid_argument for another name or l2per of a non-uniform
// target.
double discrepancyByName(const std::string &metric, std::span<const Point2> points,
                         const Target &target, int res = 256);

}  // namespace nuld
