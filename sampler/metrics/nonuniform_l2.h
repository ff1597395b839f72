#pragma once
// The non-uniform L2asd discrepancy against a target as an objective: its
// square and its exact gradient with respect to every point, integrated
// against the bilinear interpolant of the target's CDF (CdfField: exact for
// uniform and piecewise-constant targets). O(N^2) per evaluation, no sampled
// boxes and no sigmoid: the expectation of the hard multiple-corner box loss.

#include <span>

#include "sampler/metrics/cdf_field.h"
#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

class NonuniformL2asd {
 public:
  // Grid targets use their own cells (exact); others a res x res grid.
  NonuniformL2asd(const Target &target, int res = 256);

  // L2asd^2 of the points; writes its gradient unless `grad` is empty.
  double squared(std::span<const Point2> points, std::span<Point2> grad = {}) const;

 private:
  CdfField field_;
  double massSquared_;  // sum over the 4 corners of the integral of mu_c^2
};

}  // namespace nuld
