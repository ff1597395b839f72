#pragma once
// The material interface the renderer shades with. Everything is in the local
// shading frame (normal +z, tangent +x); wo and wi point away from the
// surface. A material that reflects only (transmits() false) gives f = 0 and
// pdf = 0 for wo.z <= 0 or wi.z <= 0, and the renderer flips the frame to
// the side of wo (every surface is two-sided). A transmitting material takes
// both directions on either side of a frame whose normal points outside.

#include <optional>
#include <string>

#include "materials/rgb.h"
#include "materials/vec3.h"
#include "sampler/io/content_hash.h"
#include "sampler/point.h"

namespace nuld {

// f(wo, wi) and pdf(wo, wi) of one pair of directions.
struct BsdfValue {
  Rgb f;
  double pdf{};
};

// A sampled direction and what an estimate needs of it, whatever drew it:
// the material's own sample(), a lobe table (renderer/lobe_tables.h:
// sampleRoute), a learned set or a user's sampler through either.
struct BsdfSample {
  Vec3 wi;       // unit, local frame
  Rgb f;         // the BRDF value f(wo, wi), without the cosine
  double pdf{};  // the density that drew wi, per unit solid angle, > 0: the divisor
  // The material's own sampling density at wi, which MIS weighs the BSDF
  // strategy by: pdf itself when sample() drew wi; for a table's sample the
  // material's, so that the light sample's weight, which takes the same
  // density, and this one still sum to 1 at every direction.
  // +infinity for a delta lobe's sample, which no light sample can draw:
  // the power heuristic then gives what the ray meets weight 1.
  double misPdf{};
  // Drawn from a delta lobe (smooth glass): f is then the lobe's weight over
  // |cos| and pdf the probability of the discrete choice, so that
  // f |cos| / pdf is the sample's weight as for any other sample.
  bool delta = false;
};

class Bsdf {
 public:
  virtual ~Bsdf() = default;

  virtual std::string name() const = 0;
  // Adds everything f, pdf and sample depend on (the kind and its
  // parameters) to `h`: a scene's content key (renderer/scene.h) is made of
  // these, so two materials that shade alike add the same bytes.
  virtual void hashContent(ContentHash &h) const = 0;
  // Whether wo and wi may lie on both sides (see the top of this file).
  virtual bool transmits() const { return false; }
  // Whether every lobe is a delta: f and pdf are 0 for every pair, so a
  // light sample cannot contribute and the renderer draws none.
  virtual bool onlyDelta() const { return false; }
  // f(wo, wi), without the cosine factor.
  virtual Rgb eval(Vec3 wo, Vec3 wi) const = 0;
  // The density per unit solid angle with which sample() produces wi.
  virtual double pdf(Vec3 wo, Vec3 wi) const = 0;
  // Both at once, the same values as eval and pdf; materials whose two share
  // work (half vector, microfacet D) override it.
  virtual BsdfValue evalWithPdf(Vec3 wo, Vec3 wi) const { return {eval(wo, wi), pdf(wo, wi)}; }
  // Maps (uc, u) in [0,1)^3 to a direction, pbrt-v4's form: uc chooses
  // among the material's lobes (a material of one lobe ignores it) and u
  // samples the chosen lobe; the renderer draws uc from the lobe-choice
  // domain (renderer/sample_layout.h). nullopt when no direction is produced
  // (for example a microfacet reflection that points below the surface).
  virtual std::optional<BsdfSample> sample(Vec3 wo, double uc, Point2 u) const = 0;
  // How many lobes uc chooses among (1: sample() ignores uc).
  virtual int lobeCount() const { return 1; }
  // The same distribution from the square alone, for studies of 2D sets on
  // a BSDF integrand (tools/study): u.x chooses the lobe and, rescaled,
  // stays the lobe's first coordinate. A material of one lobe: sample().
  virtual std::optional<BsdfSample> sampleSquare(Vec3 wo, Point2 u) const {
    return sample(wo, 0.0, u);
  }
};

}  // namespace nuld
