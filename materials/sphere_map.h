#pragma once
// The cylindrical equal-area map between the unit square and the sphere of
// directions (docs/architecture.md, "Domains"): (u, v) -> phi = 2 pi u, cos theta = 1 - 2v, with
// theta measured from +z. It is equal-area, so a density p(u, v) on the
// square is the density p / (4 pi) per steradian. The hemisphere z >= 0 is
// the half v in [0, 1/2].

#include <algorithm>
#include <cmath>
#include <numbers>

#include "materials/turns.h"
#include "materials/vec3.h"
#include "sampler/point.h"

namespace nuld {

inline constexpr double kInvFourPi = 1 / (4 * std::numbers::pi);

inline Vec3 sphereDirection(Point2 uv) {
  const double z = std::clamp(1 - 2 * uv.y, -1.0, 1.0);
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  const SinCos phi = sinCosTurns(uv.x);
  return {r * phi.cos, r * phi.sin, z};
}

// The inverse of sphereDirection for a unit vector; u in [0, 1).
inline Point2 spherePoint(Vec3 w) {
  const double u = std::min(atan2Turns(w.y, w.x), std::nextafter(1.0, 0.0));
  return {u, std::clamp(0.5 * (1 - w.z), 0.0, 1.0)};
}

}  // namespace nuld
