#pragma once
// Burley's 2012 "principled" Disney BRDF, with the specular transmission of
// his 2015 BSDF (docs/architecture.md, "Materials").
//
// Lobes, each a term of f:
//   diffuse     (1 - metallic) ((1 - subsurface) Fd base / pi + sheen)
//   subsurface  (1 - metallic) subsurface ss base / pi
//               (the two sum to Burley's lerp(Fd, ss, subsurface) term)
//   specular    anisotropic GGX, D F G2 / (4 cos cos), Schlick F from Cspec0
//   clearcoat   GTR1, present only when clearcoat > 0
//   transmission  (1 - metallic) spec_trans times a GGX dielectric interface
//               of index `ior` that reflects and refracts (dielectric.h),
//               present only when spec_trans > 0; the diffuse lobes then
//               carry (1 - spec_trans) and the specular 1 - (1 - metallic)
//               spec_trans, the blend of Mitsuba 3's principled BSDF
// Sampling: u.x picks one lobe (LobeChoice says with which probabilities)
// and, rescaled to [0,1) within the lobe's stripe of u.x, stays the lobe's
// first coordinate; diffuse and subsurface sample the cosine-weighted
// hemisphere, specular the GGX visible normals (Heitz 2018), clearcoat the
// GTR1 normals; the pdf is the mixture of the lobe pdfs with the choice's
// probabilities. The per-lobe functions let a caller combine the lobes
// differently (MIS over lobes).

#include <array>
#include <optional>
#include <string>

#include "materials/bsdf.h"
#include "materials/dielectric.h"
#include "materials/microfacet.h"
#include "sampler/enum_names.h"

namespace nuld {

// Every parameter of Burley 2012, with his defaults, all in [0, 1]; and
// Burley 2015's specular transmission (spec_trans in [0, 1]) with the index
// of refraction of the inside (ior in (1, 4]; the outside is air).
struct DisneyParams {
  Rgb baseColor{1, 1, 1};
  double metallic = 0, subsurface = 0, specular = 0.5, roughness = 0.5, specularTint = 0,
         anisotropic = 0, sheen = 0, sheenTint = 0, clearcoat = 0, clearcoatGloss = 1;
  double specTrans = 0, ior = 1.5;

  friend bool operator==(const DisneyParams &, const DisneyParams &) = default;
};

// Throws std::invalid_argument naming the first parameter that is not a
// finite value in [0, 1] (base colour components included), or an ior
// outside (1, 4].
void validate(const DisneyParams &params);

enum class DisneyLobe { Diffuse, Subsurface, Specular, Clearcoat, Transmission };
inline constexpr auto kDisneyLobeNames =
    enumTable<DisneyLobe>("Disney lobe", {{"diffuse", DisneyLobe::Diffuse},
                                          {"subsurface", DisneyLobe::Subsurface},
                                          {"specular", DisneyLobe::Specular},
                                          {"clearcoat", DisneyLobe::Clearcoat},
                                          {"transmission", DisneyLobe::Transmission}});
constexpr const auto &enumNames(DisneyLobe) { return kDisneyLobeNames; }

// With which probabilities sample() picks a lobe (materials/README.md,
// "Lobe choice"). The supplement picks lobes uniformly, which spends two
// thirds of a metal's samples on lobes it lacks; renderers pick them by
// what each lobe reflects.
enum class LobeChoice {
  Uniform,  // each lobe alike: the supplement's mapping (the paper's configuration)
  Weight,   // static weights, as Mitsuba 3's principled BSDF: diffuse and subsurface
            // (1 - metallic) split by subsurface, specular 1, clearcoat clearcoat / 4
  Albedo,   // each lobe's reflectance estimated at the view, as Cycles weighs its
            // closures: (1 - metallic) base luminance for the diffuse lobes, Schlick's
            // Fresnel at the view for the specular and the coat's; a tenth of the
            // choice is shared evenly by the lobes that have a value
};
inline constexpr auto kLobeChoiceNames =
    enumTable<LobeChoice>("lobe choice", {{"uniform", LobeChoice::Uniform},
                                          {"weight", LobeChoice::Weight},
                                          {"albedo", LobeChoice::Albedo}});
constexpr const auto &enumNames(LobeChoice) { return kLobeChoiceNames; }
// The classic samplers' choice, and the references'.
inline constexpr LobeChoice kDefaultLobeChoice = LobeChoice::Albedo;

class DisneyBrdf final : public Bsdf {
 public:
  // Validates the parameters (see validate).
  explicit DisneyBrdf(const DisneyParams &params, LobeChoice choice = kDefaultLobeChoice);

  const DisneyParams &params() const { return params_; }
  LobeChoice lobeChoice() const { return choice_; }

  std::string name() const override { return "disney"; }
  void hashContent(ContentHash &h) const override;
  // With spec_trans > 0 the material transmits: wo and wi may lie on either
  // side of the frame's normal, which points outside. The reflection lobes
  // are two-sided (both directions mirrored to wo's side); the transmission
  // lobe refracts into the other side, by ior entering and 1 / ior leaving.
  bool transmits() const override { return transmission_; }
  // Glass with spec_trans 1, roughness below the smooth limit and no coat:
  // only the delta lobe, which no light sample can meet.
  bool onlyDelta() const override { return onlyDelta_; }
  Rgb eval(Vec3 wo, Vec3 wi) const override;
  // The mixture of lobePdf over the lobes with lobeProbabilities(wo).
  double pdf(Vec3 wo, Vec3 wi) const override;
  // One half vector and one D per microfacet lobe for both.
  BsdfValue evalWithPdf(Vec3 wo, Vec3 wi) const override;
  // f is the full eval (all lobes) and pdf the full mixture pdf: uc picks
  // the lobe by lobeProbabilities(wo) and, rescaled within the lobe's
  // stripe, whether the transmission lobe reflects or refracts; u samples
  // the lobe. A smooth transmission lobe's sample is a delta
  // (BsdfSample::delta).
  std::optional<BsdfSample> sample(Vec3 wo, double uc, Point2 u) const override;
  std::optional<BsdfSample> sampleSquare(Vec3 wo, Point2 u) const override;

  // Lobes in sampling order: diffuse, subsurface, specular, then clearcoat
  // when clearcoat > 0 or spec_trans > 0, then transmission when
  // spec_trans > 0.
  int lobeCount() const override { return lobeCount_; }
  // The probability with which sample() picks each lobe at the view wo
  // (0 beyond lobeCount); they sum to 1 and depend on wo only through
  // |wo.z| (and, for a transmitting material, its sign), so every symmetry
  // of f that moves the view keeps them. Lobe k's stripe of u.x is [sum of
  // those before k, that plus its own).
  using LobeProbabilities = std::array<double, 5>;
  LobeProbabilities lobeProbabilities(Vec3 wo) const;
  DisneyLobe lobe(int k) const { return DisneyLobe(k); }
  // Lobe k's term of f; the terms sum to eval.
  Rgb evalLobe(int k, Vec3 wo, Vec3 wi) const;
  // The density of sampleLobe(k, ...) per unit solid angle (0 for a smooth
  // transmission lobe, a delta).
  double lobePdf(int k, Vec3 wo, Vec3 wi) const;
  // A direction from lobe k alone (uc: the transmission lobe's choice
  // between reflection and refraction); nullopt when the lobe produces none.
  std::optional<Vec3> sampleLobe(int k, Vec3 wo, Point2 u, double uc = 0.5) const;

 private:
  // The angles every lobe reads, for wo and wi above the surface.
  struct Geometry {
    Vec3 h;                   // half vector
    double cosO, cosI, cosD;  // wo.n, wi.n, wi.h (= wo.h)
    double fo, fi, fd;        // Schlick weights of those cosines
    double eta;               // the far side's index over wo's side's
  };
  static std::optional<Geometry> geometry(Vec3 wo, Vec3 wi, double eta);
  // The directions in the frame of wo's side, where every lobe is written:
  // a transmitting material seen from inside has both mirrored, and eta is
  // the far side's index over wo's side's.
  struct Side {
    Vec3 wo, wi;
    double eta;
    bool mirrored;
  };
  Side side(Vec3 wo, Vec3 wi = {}) const;
  // The lobe whose stripe of u.x holds x under `p`, and x rescaled to [0, 1)
  // within the stripe.
  struct LobePick {
    int k;
    double x;
  };
  LobePick pickLobe(const LobeProbabilities &p, double x) const;
  // Lobe k's sample at (uc, u) in the frame of wo's side, with the full f
  // and mixture pdf.
  std::optional<BsdfSample> sampleChosen(const Side &s, const LobeProbabilities &p, int k,
                                         double uc, Point2 u) const;
  // Where lobe k's stripe of u.x starts under `p`.
  static double stripeStart(const LobeProbabilities &p, int k);
  // evalWithPdf in the frame of wo's side, with the view's lobe
  // probabilities already at hand.
  BsdfValue evalWithPdf(const Side &s, const LobeProbabilities &p) const;
  // The refracted term (wi below wo's side): the transmission lobe alone.
  BsdfValue refracted(const Side &s, const LobeProbabilities &p) const;
  // The mixture of the lobes' pdfs with `p`, given each lobe's pdf.
  template <class LobePdf>
  double mixturePdf(const LobeProbabilities &p, LobePdf &&lobePdf) const;
  // The lobe's microfacet D(h) (0 for the diffuse lobes).
  double microfacetD(DisneyLobe lobe, Vec3 h) const;
  // Lobe values and pdfs given the geometry and the lobe's microfacetD.
  Rgb lobeValue(DisneyLobe lobe, Vec3 wo, Vec3 wi, const Geometry &g, double d) const;
  double lobePdf(DisneyLobe lobe, Vec3 wo, Vec3 wi, const Geometry &g, double d) const;

  DisneyParams params_;
  LobeChoice choice_;
  int lobeCount_;
  bool transmission_, onlyDelta_;
  // Whether lobe k's term of f can be non-zero: a metal has no diffuse or
  // subsurface term, a material without subsurface no subsurface term.
  // evalWithPdf skips the others (adding their exact zeros changes nothing);
  // their pdfs still count wherever the choice picks them.
  std::array<bool, 5> lobeHasValue_;
  // The parts of lobeProbabilities that do not depend on the view: the
  // static weights (Weight), or the diffuse lobes' reflectance estimates
  // and the specular and coat Fresnel's normal-incidence luminances (Albedo).
  std::array<double, 5> lobeWeight_{};
  // The blend's weights: (1 - metallic)(1 - spec_trans) on the diffuse
  // lobes, 1 - (1 - metallic) spec_trans on the specular, (1 - metallic)
  // spec_trans on the transmission; exactly (1 - metallic), 1 and 0
  // without transmission.
  double diffuseWeight_, specularWeight_, transmissionWeight_;
  Rgb tint_;              // base colour normalized to luminance 1
  Rgb specular0_;         // Cspec0: specular colour at normal incidence
  Rgb sheenColor_;        // Csheen
  Rgb transmissionTint_;  // sqrt(base colour): two crossings of a closed object give it
  GgxDistribution specular_;
  Gtr1Distribution clearcoat_;
  GgxDistribution clearcoatMasking_;  // Burley's fixed alpha 0.25 for the clearcoat's G
  DielectricInterface dielectric_;    // the transmission lobe, on the specular's GGX
};

}  // namespace nuld
