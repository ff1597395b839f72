#pragma once
// The one summary of repeated measurements that both studies report: the
// mean, the sample standard deviation (n - 1) and the standard error of the
// mean (the deviation over sqrt n).

#include <cmath>
#include <span>

namespace nuld::study {

struct MeanAndError {
  double mean = 0, std = 0, stderr_ = 0;
};

// Zero deviation and error for fewer than two values.
inline MeanAndError meanAndError(std::span<const double> v) {
  MeanAndError s;
  const double n = double(v.size());
  for (double x : v) s.mean += x / n;
  if (v.size() > 1) {
    double ss = 0;
    for (double x : v) ss += (x - s.mean) * (x - s.mean);
    s.std = std::sqrt(ss / (n - 1));
    s.stderr_ = std::sqrt(ss / (n - 1) / n);
  }
  return s;
}

}  // namespace nuld::study
