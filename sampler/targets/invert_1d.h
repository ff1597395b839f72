#pragma once
// Inverts a monotone 1D CDF on [lo, hi] by Newton steps safeguarded by
// bisection: Newton alone diverges near zero density, bisection alone is slow.

#include <cmath>

namespace nuld {

// Finds x in [lo, hi] with cdf(x) = t, given pdf = cdf'. `start` (default:
// the midpoint) is the first guess; a good one saves most of the steps.
template <typename Cdf, typename Pdf>
double invertMonotone(const Cdf &cdf, const Pdf &pdf, double t, double lo, double hi,
                      double start = NAN) {
  double x = start >= lo && start <= hi ? start : 0.5 * (lo + hi);
  double previousWidth = 2 * (hi - lo);
  for (int it = 0; it < 200; ++it) {
    const double f = cdf(x) - t;
    if (f == 0) return x;
    if (f < 0)
      lo = x;
    else
      hi = x;
    const double width = hi - lo;
    if (width <= 4e-16 * std::max(1.0, std::abs(x))) break;
    // Newton only while it shrinks the bracket fast; where the computed CDF
    // is flat over many ulps (wide Gaussians) Newton stalls, bisection never does.
    const double d = pdf(x);
    double next = d > 0 ? x - f / d : lo;
    if (!(next > lo && next < hi) || width > 0.5 * previousWidth) next = 0.5 * (lo + hi);
    previousWidth = width;
    x = next;
  }
  return 0.5 * (lo + hi);
}

}  // namespace nuld
