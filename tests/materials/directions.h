#pragma once
// Directions for the materials tests, from angles in degrees.

#include <cmath>
#include <numbers>

#include "materials/sampling.h"
#include "sampler/sequences/rng.h"

namespace nuld::test {

inline Vec3 fromAngles(double thetaDeg, double phiDeg) {
  const double t = thetaDeg * std::numbers::pi / 180, p = phiDeg * std::numbers::pi / 180;
  return sphericalDirection(std::sin(t), std::cos(t), p);
}

// A random direction of the upper hemisphere (not uniform: denser near the
// horizon, where the formulas are most fragile).
inline Vec3 randomUpper(Rng &rng) {
  return fromAngles(90 * std::sqrt(rng.uniform()), 360 * rng.uniform());
}

}  // namespace nuld::test
