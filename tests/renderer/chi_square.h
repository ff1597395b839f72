#pragma once
// Pearson's chi-square test of samples on the unit square against a density,
// the way pbrt-v4 and Mitsuba test their sampling routines: the caller bins
// the samples and gives each bin's expected count (the density integrated
// over it), bins with small expectations are pooled, and the p-value comes
// from the regularized incomplete gamma function.

#include <cmath>
#include <vector>

#include "sampler/point.h"

namespace nuld::test {

// Upper regularized incomplete gamma Q(a, x) (series / continued fraction).
inline double gammaQ(double a, double x) {
  if (x <= 0) return 1;
  const double lg = std::lgamma(a);
  if (x < a + 1) {
    double sum = 1 / a, term = sum;
    for (int n = 1; n < 1000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-15) break;
    }
    return 1 - sum * std::exp(-x + a * std::log(x) - lg);
  }
  double b = x + 1 - a, c = 1e300, d = 1 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    d = std::abs(d) < 1e-300 ? 1e-300 : d;
    c = b + an / c;
    c = std::abs(c) < 1e-300 ? 1e-300 : c;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - lg) * h;
}

class ChiSquareBins {
 public:
  explicit ChiSquareBins(std::size_t bins) : counts_(bins, 0) {}

  void add(std::size_t bin) { ++counts_.at(bin); }

  // Pools bins expecting fewer than 5 samples into one; an observed sample
  // in a bin that expects none gives p = 0.
  double pValue(const std::vector<double> &expected) const {
    double chi2 = 0, pooledE = 0, pooledO = 0;
    int dof = -1;
    for (std::size_t k = 0; k < counts_.size(); ++k) {
      if (expected[k] == 0) {
        if (counts_[k] > 0) return 0;
        continue;
      }
      if (expected[k] < 5) {
        pooledE += expected[k];
        pooledO += counts_[k];
        continue;
      }
      const double d = counts_[k] - expected[k];
      chi2 += d * d / expected[k];
      ++dof;
    }
    if (pooledE > 0) {
      const double d = pooledO - pooledE;
      chi2 += d * d / pooledE;
      ++dof;
    }
    return dof > 0 ? gammaQ(0.5 * dof, 0.5 * chi2) : 1.0;
  }

 private:
  std::vector<long> counts_;
};

}  // namespace nuld::test
