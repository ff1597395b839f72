#pragma once
// The smooth lights that measure a lobe route (renderer/README.md, "Lobe
// routes"): a constant and two gradients over the shading hemisphere, the
// kind of light interreflection gives. A route's estimates of the light
// reflected under each, repeated with fresh points, say how well it samples
// the lobe; the route with the smaller summed relative variance serves.

#include <cstddef>

#include "materials/vec3.h"

namespace nuld {

inline constexpr int kSmoothLights = 3;
inline double smoothLight(int k, Vec3 wi) {
  switch (k) {
    case 0: return 1;
    case 1: return 1 + 0.8 * (0.6 * wi.x + 0.8 * wi.z);
    default: return 1 + 0.8 * (-0.48 * wi.x + 0.6 * wi.y + 0.64 * wi.z);
  }
}

// The relative variances (variance / mean^2) of each light's repeated
// estimates, summed: `sums[k]` holds light k's estimates (any container).
template <class Sums>
double summedRelativeVariance(const Sums &sums) {
  double total = 0;
  for (const auto &e : sums) {
    const double n = double(std::size(e));
    double mean = 0, ss = 0;
    for (double v : e) mean += v / n;
    for (double v : e) ss += (v - mean) * (v - mean);
    if (mean > 0) total += ss / (n - 1) / (mean * mean);
  }
  return total;
}

}  // namespace nuld
