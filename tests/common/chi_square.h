#pragma once
// Pearson's chi-square test shared by every module's sampling tests (the
// pbrt-v4 / Mitsuba method): the caller bins samples and integrates the
// claimed density over each bin; bins expected below 5 are pooled, and the
// p-value comes from the regularized incomplete gamma function.

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace nuld::test {

// The per-test level that keeps the chance of any false failure among
// `tests` tests at `overall` (Sidak correction).
inline double sidakLevel(double overall, int tests) {
  return 1 - std::pow(1 - overall, 1.0 / tests);
}

// Regularized upper incomplete gamma Q(a, x): the series for P when
// x < a + 1, the continued fraction (modified Lentz) otherwise.
inline double regularizedGammaQ(double a, double x) {
  if (!(x > 0)) return 1;
  const double logPrefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1) {
    double term = 1 / a, sum = term;
    for (int n = 1; n < 100000 && std::abs(term) > 1e-17 * std::abs(sum); ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return std::clamp(1 - sum * std::exp(logPrefix), 0.0, 1.0);
  }
  constexpr double kTiny = 1e-300;
  double b = x + 1 - a, c = 1 / kTiny, d = 1 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1) < 1e-16) break;
  }
  return std::clamp(std::exp(logPrefix) * h, 0.0, 1.0);
}

struct ChiSquare {
  double statistic = 0;
  int dof = 0;
  double pValue = 1;
  std::string note;  // why the test failed outright, if it did
};

// Pearson's statistic with bins expected below `minExpected` pooled into one.
inline ChiSquare pooledChiSquare(const std::vector<double> &observed,
                                 const std::vector<double> &expected, double minExpected = 5) {
  ChiSquare r;
  double pooledObs = 0, pooledExp = 0;
  int bins = 0;
  for (std::size_t k = 0; k < observed.size(); ++k) {
    if (expected[k] <= 0 && observed[k] > 0) {
      r.note = "bin " + std::to_string(k) + " has " + std::to_string(int(observed[k])) +
               " samples where the pdf integrates to 0";
      r.pValue = 0;
      r.statistic = std::numeric_limits<double>::infinity();
      return r;
    }
    if (expected[k] < minExpected) {
      pooledObs += observed[k];
      pooledExp += expected[k];
      continue;
    }
    const double d = observed[k] - expected[k];
    r.statistic += d * d / expected[k];
    ++bins;
  }
  if (pooledExp > 0) {
    const double d = pooledObs - pooledExp;
    r.statistic += d * d / pooledExp;
    ++bins;
  }
  r.dof = std::max(1, bins - 1);
  r.pValue = regularizedGammaQ(0.5 * r.dof, 0.5 * r.statistic);
  return r;
}

}  // namespace nuld::test
