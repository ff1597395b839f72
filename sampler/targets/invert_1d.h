#pragma once
// Inverts a monotone 1D CDF on [lo, hi] by Newton steps safeguarded by
// bisection: Newton alone diverges near zero density, bisection alone is slow.

#include <cmath>

namespace nuld {

// Finds x in [lo, hi] with cdf(x) = t, given pdf = cdf'.
template <typename Cdf, typename Pdf>
double invertMonotone(const Cdf &cdf, const Pdf &pdf, double t, double lo, double hi) {
  double x = 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const double f = cdf(x) - t;
    if (f == 0) return x;
    if (f < 0) lo = x; else hi = x;
    if (hi - lo <= 1e-16 * std::max(1.0, std::abs(x))) break;
    const double d = pdf(x);
    double next = d > 0 ? x - f / d : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 1e-17) return next;
    x = next;
  }
  return 0.5 * (lo + hi);
}

}  // namespace nuld
