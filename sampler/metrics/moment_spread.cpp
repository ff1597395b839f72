#include "sampler/metrics/moment_spread.h"

#include <array>
#include <cmath>
#include <stdexcept>

namespace nuld {

MomentSpread momentSpread(const PointSet &set) {
  const std::size_t K = set.instances();
  if (K < 2)
    throw std::invalid_argument("the spread of the sets' means needs at least two instances");
  // Per instance the means; then their sample standard deviations.
  std::array<double, 3> sum{}, sq{};
  for (std::size_t k = 0; k < K; ++k) {
    std::array<double, 3> m{};
    for (const Point2 &p : set.instance(k)) m[0] += p.x, m[1] += p.y, m[2] += p.x * p.y;
    for (int c = 0; c < 3; ++c) {
      m[c] /= double(set.n);
      sum[c] += m[c];
      sq[c] += m[c] * m[c];
    }
  }
  std::array<double, 3> sd{};
  for (int c = 0; c < 3; ++c) {
    const double mean = sum[c] / double(K);
    sd[c] = std::sqrt(std::max(0.0, (sq[c] - double(K) * mean * mean) / double(K - 1)));
  }
  return {sd[0], sd[1], sd[2]};
}

}  // namespace nuld
