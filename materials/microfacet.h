#pragma once
// Microfacet distributions in the local frame (normal +z, tangent +x):
// anisotropic GGX (Trowbridge-Reitz) with Smith masking and Heitz's 2018
// visible-normal sampling, and Burley's GTR1 for the clearcoat.
//
// Masking-shadowing is the height-correlated Smith G2 = 1 / (1 + L(wo) + L(wi))
// (Heitz 2014), not the separable G1(wo) G1(wi) of Burley's 2012 notes: it is
// the more accurate of the two, and it is reciprocal too.
//
// Terms that divide by cos theta are written so that the division cancels
// (see visibility and reflectionPdf): they stay finite down to grazing
// angles and for alpha at its floor.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "materials/vec3.h"
#include "sampler/point.h"

namespace nuld {

// (1 - cos)^5, the weight in Schlick's Fresnel F = F0 + (1 - F0) w. Inline,
// like D, visibility and stretchedLength below: every Disney eval calls them.
inline double schlickWeight(double cosTheta) {
  const double m = std::clamp(1 - cosTheta, 0.0, 1.0);
  const double m2 = m * m;
  return m2 * m2 * m;
}

class GgxDistribution {
 public:
  // The smallest alpha; roughness 0 maps to it. D then peaks at
  // 1 / (pi alpha^2) ~ 3e7, so D, G and the pdf stay finite, while the lobe
  // (about 1e-4 rad wide) is already sharper than any renderer needs.
  static constexpr double kMinAlpha = 1e-4;

  // Alphas below kMinAlpha (roughness 0 included) are raised to it.
  GgxDistribution(double alphaX, double alphaY);

  double alphaX() const { return ax_; }
  double alphaY() const { return ay_; }

  // Microfacet normal density; integral of D(m) m.z over the hemisphere = 1.
  double D(Vec3 m) const {
    if (!(m.z > 0)) return 0;
    // cos^4 theta (1 + tan^2 theta (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2,
    // multiplied out so that no tangent appears (m is unit).
    const double x = m.x / ax_, y = m.y / ay_;
    const double e = x * x + y * y + m.z * m.z;
    return 1 / (std::numbers::pi * ax_ * ay_ * e * e);
  }
  // Smith's auxiliary function; +infinity for w.z <= 0.
  double lambda(Vec3 w) const;
  // Masking 1 / (1 + lambda(w)), in [0, 1]; 0 for w.z <= 0.
  double G1(Vec3 w) const;
  // Height-correlated masking-shadowing 1 / (1 + lambda(wo) + lambda(wi)).
  double G2(Vec3 wo, Vec3 wi) const;
  // G2 / (4 wo.z wi.z), the factor of the specular BRDF besides D and F;
  // 0 unless both are above the surface.
  double visibility(Vec3 wo, Vec3 wi) const {
    if (!(wo.z > 0) || !(wi.z > 0)) return 0;
    // G2 / (4 wo.z wi.z) with the cosines cancelled.
    return 0.5 / (stretchedLength(wo) * wi.z + stretchedLength(wi) * wo.z);
  }

  // Visible-normal density D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z.
  double visibleD(Vec3 wo, Vec3 m) const;
  // Draws m from D_wo (Heitz 2018): u.x picks the radius, u.y the angle on
  // the disc the stretched hemisphere projects to. Requires wo.z > 0.
  Vec3 sampleVisibleNormal(Vec3 wo, Point2 u) const;

  // The density of wi = reflect(wo, m) with m ~ D_wo, per unit solid angle:
  // D_wo(h) / (4 wo.h) = G1(wo) D(h) / (4 wo.z), h the half vector; 0 unless
  // wo and wi are both above the surface.
  double reflectionPdf(Vec3 wo, Vec3 wi) const;
  // The same for a valid half vector whose D(h) the caller already has.
  double reflectionPdfGivenD(Vec3 wo, double dOfH) const {
    return dOfH / (2 * (wo.z + stretchedLength(wo)));
  }
  // nullopt when the reflected direction points below the surface.
  std::optional<Vec3> sampleReflection(Vec3 wo, Point2 u) const;

 private:
  // sqrt(w.z^2 + (ax w.x)^2 + (ay w.y)^2): lambda(w) = (s / w.z - 1) / 2.
  double stretchedLength(Vec3 w) const {
    const double x = ax_ * w.x, y = ay_ * w.y;
    return std::sqrt(x * x + y * y + w.z * w.z);
  }

  // The stretched view and a basis around it, in which sampleVisibleNormal
  // draws its disc point.
  struct VisibleFrame {
    Vec3 vh, t1, t2;
  };
  VisibleFrame visibleFrame(Vec3 wo) const;

  double ax_, ay_;
};

// Burley's "generalized Trowbridge-Reitz" with exponent 1, isotropic: the
// long-tailed clearcoat distribution. Sampled by its normals (pdf D(m) m.z),
// not by visible normals, as in Burley's notes.
class Gtr1Distribution {
 public:
  // alpha in (0, 1]; clamped to GgxDistribution::kMinAlpha below.
  explicit Gtr1Distribution(double alpha);

  double alpha() const { return alpha_; }
  // Integral of D(m) m.z over the hemisphere = 1.
  double D(Vec3 m) const;
  // m with density D(m) m.z.
  Vec3 sampleNormal(Point2 u) const;

  // The density of wi = reflect(wo, m), m ~ D(m) m.z, per unit solid angle:
  // D(h) h.z / (4 wo.h). Normals facing away from wo (wo.m <= 0) are not
  // reflected (sampleReflection gives nullopt), so their mass is missing
  // here as well.
  double reflectionPdf(Vec3 wo, Vec3 wi) const;
  // The same for a valid half vector h whose D(h) the caller already has.
  double reflectionPdfGivenD(Vec3 wo, Vec3 h, double dOfH) const;
  std::optional<Vec3> sampleReflection(Vec3 wo, Point2 u) const;

 private:
  double alpha_;
};

// The half vector of two directions above the surface; nullopt when it is
// undefined (wo = -wi) or not above the surface.
// Inline: every microfacet eval and pdf starts here.
inline std::optional<Vec3> halfVector(Vec3 wo, Vec3 wi) {
  const Vec3 h = wo + wi;
  const double len2 = lengthSquared(h);
  if (!(len2 > 0) || !(h.z > 0)) return std::nullopt;
  return h / std::sqrt(len2);
}

}  // namespace nuld
