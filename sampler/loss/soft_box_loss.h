#pragma once
// The soft box discrepancy of Algorithm 1 and its analytic gradient:
//
//   L = (1/M) sum_m r_m^2,   r_m = (1/N) sum_i sigma(alpha d(A_m, x_i)) - mu(A_m),
//   dL/dx_i = (2 alpha / (M N)) sum_m r_m sigma'(alpha d_mi) dd_mi/dx_i,
//
// with d(A, x) = min over the box's sides of the signed distance to that side
// (> 0 inside). Pairs with |alpha d| > cutoff have sigma exactly 0 or 1 to
// double precision and no gradient; a PointGrid lets each box visit only the
// band of points near its boundary and count the interior by whole cells.
//
// Deterministic: boxes are split into a fixed number of chunks whose partial
// sums are reduced in a fixed order, so results do not depend on threads.

#include <span>

#include "sampler/point.h"

namespace nuld {

// How the kernel evaluates sigma (soft_box_loss.cpp says more): Direct
// computes one exp per point-box pair and first sorts the scanned points
// into inside, outside and band; Factored multiplies per-point and per-box
// exponentials and needs points in the unit square and alpha / 16 + cutoff
// <= 700. Automatic picks Factored for bands wider than a grid cell, where
// it is the faster, and Direct otherwise. All agree to about 1e-13.
enum class SoftBoxKernel { Automatic, Direct, Factored };

struct SoftBoxLossOptions {
  double alpha = 20;
  // |alpha d| beyond which sigma is treated as exactly 0 or 1: at 36 the
  // neglected tail is below 2.4e-16 per pair.
  double cutoff = 36;
  SoftBoxKernel kernel = SoftBoxKernel::Automatic;
};

// Returns L; writes dL/dx into `grad` (same size as `points`) unless empty.
// `masses[m]` is the target mass of boxes[m].
double softBoxLoss(std::span<const Point2> points, std::span<const Box2> boxes,
                   std::span<const double> masses, const SoftBoxLossOptions &options,
                   std::span<Point2> grad = {});

// The definition itself, O(N M), every pair through safeSigmoid with no
// cutoff, culling or vectors: the reference the kernels are tested against.
double softBoxLossReference(std::span<const Point2> points, std::span<const Box2> boxes,
                            std::span<const double> masses, double alpha,
                            std::span<Point2> grad = {});

// The same with hard indicators (alpha -> infinity): a reference, O(N M).
double hardBoxLoss(std::span<const Point2> points, std::span<const Box2> boxes,
                   std::span<const double> masses);

// Numerically safe logistic function: no overflow for any finite t.
inline double safeSigmoid(double t);

}  // namespace nuld

#include <cmath>

inline double nuld::safeSigmoid(double t) {
  const double e = std::exp(-std::abs(t));
  return t >= 0 ? 1 / (1 + e) : e / (1 + e);
}
