#pragma once
// Burley's 2012 "principled" Disney BRDF, reflection only
// (docs/architecture.md, "Materials").
//
// Lobes, each a term of f:
//   diffuse     (1 - metallic) ((1 - subsurface) Fd base / pi + sheen)
//   subsurface  (1 - metallic) subsurface ss base / pi
//               (the two sum to Burley's lerp(Fd, ss, subsurface) term)
//   specular    anisotropic GGX, D F G2 / (4 cos cos), Schlick F from Cspec0
//   clearcoat   GTR1, present only when clearcoat > 0
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
#include "materials/microfacet.h"
#include "sampler/enum_names.h"

namespace nuld {

// Every parameter of Burley 2012, with his defaults; all in [0, 1].
struct DisneyParams {
  Rgb baseColor{1, 1, 1};
  double metallic = 0, subsurface = 0, specular = 0.5, roughness = 0.5, specularTint = 0,
         anisotropic = 0, sheen = 0, sheenTint = 0, clearcoat = 0, clearcoatGloss = 1;

  friend bool operator==(const DisneyParams &, const DisneyParams &) = default;
};

// Throws std::invalid_argument naming the first parameter that is not a
// finite value in [0, 1] (base colour components included).
void validate(const DisneyParams &params);

enum class DisneyLobe { Diffuse, Subsurface, Specular, Clearcoat };
inline constexpr auto kDisneyLobeNames =
    enumTable<DisneyLobe>("Disney lobe", {{"diffuse", DisneyLobe::Diffuse},
                                          {"subsurface", DisneyLobe::Subsurface},
                                          {"specular", DisneyLobe::Specular},
                                          {"clearcoat", DisneyLobe::Clearcoat}});
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
  Rgb eval(Vec3 wo, Vec3 wi) const override;
  // The mixture of lobePdf over the lobes with lobeProbabilities(wo).
  double pdf(Vec3 wo, Vec3 wi) const override;
  // One half vector and one D per microfacet lobe for both.
  BsdfValue evalWithPdf(Vec3 wo, Vec3 wi) const override;
  // f is the full eval (all lobes) and pdf the full mixture pdf: uc picks
  // the lobe by lobeProbabilities(wo), u samples it.
  std::optional<BsdfSample> sample(Vec3 wo, double uc, Point2 u) const override;
  std::optional<BsdfSample> sampleSquare(Vec3 wo, Point2 u) const override;

  // Lobes in sampling order: diffuse, subsurface, specular, then clearcoat
  // when clearcoat > 0.
  int lobeCount() const override { return lobeCount_; }
  // The probability with which sample() picks each lobe at the view wo
  // (0 beyond lobeCount); they sum to 1 and depend on wo only through wo.z,
  // so every symmetry of f that moves the view keeps them. Lobe k's stripe
  // of u.x is [sum of those before k, that plus its own).
  using LobeProbabilities = std::array<double, 4>;
  LobeProbabilities lobeProbabilities(Vec3 wo) const;
  DisneyLobe lobe(int k) const { return DisneyLobe(k); }
  // Lobe k's term of f; the terms sum to eval.
  Rgb evalLobe(int k, Vec3 wo, Vec3 wi) const;
  // The density of sampleLobe(k, ...) per unit solid angle.
  double lobePdf(int k, Vec3 wo, Vec3 wi) const;
  // A direction from lobe k alone; nullopt when it points below the surface.
  std::optional<Vec3> sampleLobe(int k, Vec3 wo, Point2 u) const;

 private:
  // The angles every lobe reads, for wo and wi above the surface.
  struct Geometry {
    Vec3 h;                   // half vector
    double cosO, cosI, cosD;  // wo.n, wi.n, wi.h (= wo.h)
    double fo, fi, fd;        // Schlick weights of those cosines
  };
  static std::optional<Geometry> geometry(Vec3 wo, Vec3 wi);
  // The lobe whose stripe of u.x holds x under `p`, and x rescaled to [0, 1)
  // within the stripe.
  struct LobePick {
    int k;
    double x;
  };
  LobePick pickLobe(const LobeProbabilities &p, double x) const;
  // Lobe k's sample at u, with the full f and mixture pdf.
  std::optional<BsdfSample> sampleChosen(Vec3 wo, const LobeProbabilities &p, int k,
                                         Point2 u) const;
  // Where lobe k's stripe of u.x starts under `p`.
  static double stripeStart(const LobeProbabilities &p, int k);
  // evalWithPdf with the view's lobe probabilities already at hand.
  BsdfValue evalWithPdf(Vec3 wo, Vec3 wi, const LobeProbabilities &p) const;
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
  // Whether lobe k's term of f can be non-zero: a metal has no diffuse or
  // subsurface term, a material without subsurface no subsurface term.
  // evalWithPdf skips the others (adding their exact zeros changes nothing);
  // their pdfs still count wherever the choice picks them.
  std::array<bool, 4> lobeHasValue_;
  // The parts of lobeProbabilities that do not depend on the view: the
  // static weights (Weight), or the diffuse lobes' reflectance estimates
  // and the specular and coat Fresnel's normal-incidence luminances (Albedo).
  std::array<double, 4> lobeWeight_{};
  Rgb tint_;        // base colour normalized to luminance 1
  Rgb specular0_;   // Cspec0: specular colour at normal incidence
  Rgb sheenColor_;  // Csheen
  GgxDistribution specular_;
  Gtr1Distribution clearcoat_;
  GgxDistribution clearcoatMasking_;  // Burley's fixed alpha 0.25 for the clearcoat's G
};

}  // namespace nuld
