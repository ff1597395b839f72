#pragma once
// A dielectric interface: the exact Fresnel term and a GGX interface that
// reflects and refracts (Walter et al. 2007), sampled by visible normals
// (Heitz 2018). It is the transmitting lobe of the Disney BSDF (disney.h),
// in the frame of the view's side: every function takes wo.z > 0, and eta is
// the index of refraction of the far side (where refracted directions go)
// over that of wo's side, so the caller passes ior outside and 1 / ior
// inside.
//
// Transport is radiance's (camera paths): a refracted f carries 1 / eta^2,
// as pbrt-v4's TransportMode::Radiance does, since radiance crossing into a
// denser medium is compressed into a smaller solid angle. A path that enters
// and leaves a closed object multiplies the two factors back to 1.

#include <optional>

#include "materials/microfacet.h"
#include "materials/vec3.h"
#include "sampler/point.h"

namespace nuld {

// The unpolarized Fresnel reflectance of a smooth interface for light
// arriving at cosThetaI (clamped to [0, 1]) on the near side; eta = far /
// near. 1 under total internal reflection.
double fresnelDielectric(double cosThetaI, double eta);

// w (pointing away from the surface, w.n > 0) refracted through the
// interface of normal n into the far side; eta = far / near. nullopt under
// total internal reflection.
std::optional<Vec3> refract(Vec3 w, Vec3 n, double eta);

class DielectricInterface {
 public:
  // An interface whose largest alpha is below this is smooth: a delta lobe,
  // as pbrt-v4's EffectivelySmooth rule; a GGX lobe that narrow is a
  // mirror to the renderer, and sampling it by densities near 1e7 only
  // adds noise.
  static constexpr double kSmoothAlpha = 1e-3;

  explicit DielectricInterface(GgxDistribution distribution) : d_(distribution) {}

  bool smooth() const { return std::max(d_.alphaX(), d_.alphaY()) < kSmoothAlpha; }

  // The probability that sample() reflects rather than refracts. Smooth:
  // the Fresnel reflectance at the view, so each sample's weight is 1.
  // Rough: the same, kept within [0.1, 0.9], because a microfacet can
  // refract (or reflect) where the mean surface would not.
  double reflectProbability(double cosThetaO, double eta) const;

  // f (without tint, the cosine excluded) and the density of sample() at
  // wi: reflection for wi.z > 0, refraction for wi.z < 0. Both are 0 for a
  // smooth interface, whose lobe is a delta no direction is evaluated at.
  struct Value {
    double f = 0, pdf = 0;
  };
  Value eval(Vec3 wo, Vec3 wi, double eta) const;

  // A direction: uc < reflectProbability reflects, otherwise refracts; u
  // draws the microfacet normal (ignored when smooth). For a smooth
  // interface f and pdf are the delta's weights: f = F / |cos| (or the
  // refracted (1 - F) / (eta^2 |cos|)) and pdf the discrete probability, so
  // f |cos| / pdf is the sample's weight as for any other lobe. nullopt when
  // the microfacet sends the direction to the wrong side or reflects totally.
  struct Sample {
    Vec3 wi;
    double f = 0, pdf = 0;
    bool delta = false;
  };
  std::optional<Sample> sample(Vec3 wo, double uc, Point2 u, double eta) const;

 private:
  GgxDistribution d_;
};

}  // namespace nuld
