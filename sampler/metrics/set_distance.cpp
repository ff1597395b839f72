#include "sampler/metrics/set_distance.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace nuld {
namespace {

// Mean over the points of a of the distance to the nearest point of b.
double meanNearest(std::span<const Point2> a, std::span<const Point2> b) {
  double sum = 0;
  for (const Point2 &p : a) {
    double best = std::numeric_limits<double>::infinity();
    for (const Point2 &q : b) {
      const double dx = p.x - q.x, dy = p.y - q.y;
      best = std::min(best, dx * dx + dy * dy);
    }
    sum += std::sqrt(best);
  }
  return sum / double(a.size());
}

}  // namespace

double meanSetDistance(const PointSet &set) {
  const std::size_t K = set.instances();
  if (K < 2) throw std::invalid_argument("set distance needs at least two instances");
  double sum = 0;
  for (std::size_t k = 0; k < K; ++k)
    for (std::size_t l = k + 1; l < K; ++l)
      sum += 0.5 * (meanNearest(set.instance(k), set.instance(l)) +
                    meanNearest(set.instance(l), set.instance(k)));
  return sum / double(K * (K - 1) / 2);
}

}  // namespace nuld
