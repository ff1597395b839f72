#pragma once
// Directions from angles, and the cosine-weighted hemisphere sampling shared
// by the Lambertian and the Disney diffuse and subsurface lobes.

#include <algorithm>
#include <cmath>
#include <numbers>

#include "materials/turns.h"
#include "materials/vec3.h"
#include "sampler/point.h"

namespace nuld {

inline constexpr double kInvPi = std::numbers::inv_pi;

// The unit vector at polar angle theta (from +z) and azimuth phi (from +x).
inline Vec3 sphericalDirection(double sinTheta, double cosTheta, double phi) {
  return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

// The same with the azimuth in turns (phi = 2 pi turns), as samplers draw it.
inline Vec3 sphericalDirectionTurns(double sinTheta, double cosTheta, double turns) {
  const SinCos phi = sinCosTurns(turns);
  return {sinTheta * phi.cos, sinTheta * phi.sin, cosTheta};
}

// Cosine-weighted direction about +z by inversion of its CDF: sin^2 theta =
// u.x, phi = 2 pi u.y. Unlike the concentric-disc map, this is the plain
// inverse CDF the supplement's "deterministic mapping" refers to, and every
// u in [0,1)^2 gives cos theta = sqrt(1 - u.x) > 0, so a point such as
// Sobol's (0, 0) never yields a horizon direction with zero pdf.
inline Vec3 cosineHemisphere(Point2 u) {
  const double sin2 = std::clamp(u.x, 0.0, 1.0);
  const double sinTheta = std::sqrt(sin2), cosTheta = std::sqrt(1 - sin2);
  return sphericalDirectionTurns(sinTheta, cosTheta, u.y);
}

// The MIS weight of strategy A against B (Veach's power heuristic, exponent
// 2); written with the ratio so that pdfs whose squares underflow (or
// overflow) still give weights that sum to one.
inline double powerHeuristic(double pdfA, double pdfB) {
  if (!(pdfA > 0)) return 0.0;
  const double r = pdfB / pdfA;
  return 1 / (1 + r * r);
}

// The density of cosineHemisphere per unit solid angle.
inline double cosineHemispherePdf(double cosTheta) { return cosTheta > 0 ? cosTheta * kInvPi : 0; }

}  // namespace nuld
