#include "materials/disney.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "materials/sampling.h"

namespace nuld {
namespace {

// The roughness-derived alphas of Burley's anisotropic GGX: the aspect ratio
// stretches the lobe along the tangent, at most 1 : 0.19 in alpha^2.
GgxDistribution burleyGgx(const DisneyParams &p) {
  const double aspect = std::sqrt(1 - 0.9 * p.anisotropic);
  const double alpha = p.roughness * p.roughness;
  return {alpha / aspect, alpha * aspect};  // GgxDistribution clamps to kMinAlpha
}

double lerp(double t, double a, double b) { return (1 - t) * a + t * b; }

const DisneyParams &validated(const DisneyParams &p) {
  validate(p);
  return p;
}

}  // namespace

void validate(const DisneyParams &p) {
  auto check = [](const char *name, double v) {
    if (!(v >= 0 && v <= 1))
      throw std::invalid_argument(std::string("Disney BRDF: ") + name + " = " + std::to_string(v) +
                                  " (expected a value in [0, 1])");
  };
  check("baseColor.r", p.baseColor.r);
  check("baseColor.g", p.baseColor.g);
  check("baseColor.b", p.baseColor.b);
  check("metallic", p.metallic);
  check("subsurface", p.subsurface);
  check("specular", p.specular);
  check("roughness", p.roughness);
  check("specularTint", p.specularTint);
  check("anisotropic", p.anisotropic);
  check("sheen", p.sheen);
  check("sheenTint", p.sheenTint);
  check("clearcoat", p.clearcoat);
  check("clearcoatGloss", p.clearcoatGloss);
}

DisneyBrdf::DisneyBrdf(const DisneyParams &params, LobeChoice choice)
    : params_(validated(params)),
      choice_(choice),
      lobeCount_(params.clearcoat > 0 ? 4 : 3),
      specular_(burleyGgx(params)),
      clearcoat_(lerp(params.clearcoatGloss, 0.1, 0.001)),
      clearcoatMasking_(0.25, 0.25) {
  const bool metal = params.metallic >= 1;
  lobeHasValue_ = {!metal, !metal && params.subsurface > 0, true, params.clearcoat > 0};
  const Rgb base = params.baseColor;
  // Tints carry the hue of the base colour, not its brightness. Burley weighs
  // luminance .3/.6/.1; we use Rec. 709 like the rest of the renderer.
  const double lum = base.luminance();
  tint_ = lum > 0 ? base / lum : Rgb::grey(1);
  specular0_ = lerp(params.metallic,
                    params.specular * 0.08 * lerp(params.specularTint, Rgb::grey(1), tint_), base);
  sheenColor_ = lerp(params.sheenTint, Rgb::grey(1), tint_);
  const double dielectric = 1 - params.metallic;
  if (choice == LobeChoice::Weight)
    lobeWeight_ = {dielectric * (1 - params.subsurface), dielectric * params.subsurface, 1,
                   params.clearcoat / 4};
  else if (choice == LobeChoice::Albedo)
    lobeWeight_ = {dielectric * (1 - params.subsurface) * lum, dielectric * params.subsurface * lum,
                   specular0_.luminance(), 0.25 * params.clearcoat};
}

DisneyBrdf::LobeProbabilities DisneyBrdf::lobeProbabilities(Vec3 wo) const {
  LobeProbabilities p{};
  if (choice_ == LobeChoice::Uniform) {
    for (int k = 0; k < lobeCount_; ++k) p[k] = 1.0 / lobeCount_;
    return p;
  }
  LobeProbabilities estimate = lobeWeight_;
  if (choice_ == LobeChoice::Albedo) {
    // Schlick's Fresnel at the view: the specular lobe from Cspec0, the
    // coat from its fixed F0 = 0.04.
    const double fo = schlickWeight(std::clamp(wo.z, 0.0, 1.0));
    estimate[2] = lerp(fo, estimate[2], 1.0);
    estimate[3] *= lerp(fo, 0.04, 1.0);
  }
  double total = 0;
  int valued = 0;
  for (int k = 0; k < lobeCount_; ++k) {
    total += estimate[k];
    valued += lobeHasValue_[k];
  }
  if (!(total > 0)) {  // nothing estimated (a black, non-specular Albedo at normal view)
    for (int k = 0; k < lobeCount_; ++k) p[k] = lobeHasValue_[k] ? 1.0 / valued : 0;
    return p;
  }
  // Albedo keeps a tenth for the lobes with a value, since an estimate can
  // vanish where the lobe does not (a specular 0 still reflects at grazing
  // half-angles); Weight is Mitsuba's as it is, and never vanishes there.
  const double even = choice_ == LobeChoice::Albedo ? 0.1 : 0.0;
  for (int k = 0; k < lobeCount_; ++k)
    p[k] = (1 - even) * estimate[k] / total + (lobeHasValue_[k] ? even / valued : 0);
  return p;
}

DisneyBrdf::LobePick DisneyBrdf::pickLobe(const LobeProbabilities &p, double x) const {
  x = std::clamp(x, 0.0, 1.0);
  const double below1 = std::nextafter(1.0, 0.0);
  if (choice_ == LobeChoice::Uniform) {
    // The supplement's arithmetic, kept so that its renders are reproduced.
    const double scaled = x * lobeCount_;
    const int k = std::min(int(scaled), lobeCount_ - 1);
    return {k, std::clamp(scaled - k, 0.0, below1)};
  }
  double start = 0;
  int k = 0, last = 0;
  for (; k < lobeCount_; ++k) {
    if (!(p[k] > 0)) continue;
    last = k;
    if (x < start + p[k]) break;
    start += p[k];
  }
  if (k == lobeCount_) {  // x at the top edge (or lost to rounding): the last stripe
    k = last;
    start = stripeStart(p, k);
  }
  return {k, std::clamp((x - start) / p[k], 0.0, below1)};
}

double DisneyBrdf::stripeStart(const LobeProbabilities &p, int k) {
  double start = 0;
  for (int j = 0; j < k; ++j) start += p[j];
  return start;
}

template <class LobePdf>
double DisneyBrdf::mixturePdf(const LobeProbabilities &p, LobePdf &&lobePdf) const {
  double sum = 0;
  if (choice_ == LobeChoice::Uniform) {
    for (int k = 0; k < lobeCount_; ++k) sum += lobePdf(k);
    return sum / lobeCount_;
  }
  for (int k = 0; k < lobeCount_; ++k)
    if (p[k] > 0) sum += p[k] * lobePdf(k);
  return sum;
}

// Forced inline into its two callers (this file only): the call and the
// optional's copy were a visible share of every eval.
[[gnu::always_inline]] inline std::optional<DisneyBrdf::Geometry> DisneyBrdf::geometry(Vec3 wo,
                                                                                       Vec3 wi) {
  if (!(wo.z > 0) || !(wi.z > 0)) return std::nullopt;
  const auto h = halfVector(wo, wi);
  if (!h) return std::nullopt;
  Geometry g;
  g.h = *h;
  g.cosO = wo.z;
  g.cosI = wi.z;
  g.cosD = std::clamp(dot(wi, *h), 0.0, 1.0);
  g.fo = schlickWeight(g.cosO);
  g.fi = schlickWeight(g.cosI);
  g.fd = schlickWeight(g.cosD);
  return g;
}

double DisneyBrdf::microfacetD(DisneyLobe lobe, Vec3 h) const {
  switch (lobe) {
    case DisneyLobe::Specular: return specular_.D(h);
    case DisneyLobe::Clearcoat: return clearcoat_.D(h);
    default: return 0;
  }
}

Rgb DisneyBrdf::lobeValue(DisneyLobe lobe, Vec3 wo, Vec3 wi, const Geometry &g, double d) const {
  const DisneyParams &p = params_;
  const double cosD2 = g.cosD * g.cosD;
  switch (lobe) {
    case DisneyLobe::Diffuse: {
      // Retro-reflection: grazing light and view brighten rough surfaces
      // (fd90 > 1) and darken smooth ones (fd90 < 1).
      const double fd90 = 0.5 + 2 * p.roughness * cosD2;
      const double fd = (1 + (fd90 - 1) * g.fi) * (1 + (fd90 - 1) * g.fo);
      const Rgb sheen = p.sheen * g.fd * sheenColor_;
      return (1 - p.metallic) * ((1 - p.subsurface) * fd * kInvPi * p.baseColor + sheen);
    }
    case DisneyLobe::Subsurface: {
      // Burley's Hanrahan-Krueger-like flattening; the 1/(cos + cos) term
      // lifts grazing response the way thin scattering layers do.
      const double fss90 = p.roughness * cosD2;
      const double fss = (1 + (fss90 - 1) * g.fi) * (1 + (fss90 - 1) * g.fo);
      const double ss = 1.25 * (fss * (1 / (g.cosI + g.cosO) - 0.5) + 0.5);
      return (1 - p.metallic) * p.subsurface * ss * kInvPi * p.baseColor;
    }
    case DisneyLobe::Specular: {
      const Rgb fresnel = lerp(g.fd, specular0_, Rgb::grey(1));
      return d * specular_.visibility(wo, wi) * fresnel;
    }
    case DisneyLobe::Clearcoat: {
      if (!(p.clearcoat > 0)) return {};
      // A fixed-IOR (1.5, F0 = 0.04) varnish whose weight 0.25 Burley chose
      // to keep the coat subtle.
      const double fresnel = lerp(g.fd, 0.04, 1.0);
      return Rgb::grey(0.25 * p.clearcoat * fresnel * d * clearcoatMasking_.visibility(wo, wi));
    }
  }
  return {};
}

// f alone: the lobe terms evalWithPdf sums, in the same order, without the
// lobe probabilities and pdfs (the light integrator's weights need no
// material pdf). Both loops call lobeValue per lobe, so the two f agree
// (disney_energy_test.cpp); sample() returns evalWithPdf's.
Rgb DisneyBrdf::eval(Vec3 wo, Vec3 wi) const {
  const auto g = geometry(wo, wi);
  if (!g) return {};
  Rgb f;
  for (int k = 0; k < lobeCount_; ++k)
    if (lobeHasValue_[k]) f += lobeValue(lobe(k), wo, wi, *g, microfacetD(lobe(k), g->h));
  return f;
}

Rgb DisneyBrdf::evalLobe(int k, Vec3 wo, Vec3 wi) const {
  const auto g = geometry(wo, wi);
  if (!g || k < 0 || k >= lobeCount_) return {};
  return lobeValue(lobe(k), wo, wi, *g, microfacetD(lobe(k), g->h));
}

double DisneyBrdf::lobePdf(int k, Vec3 wo, Vec3 wi) const {
  if (!(wo.z > 0) || !(wi.z > 0) || k < 0 || k >= lobeCount_) return 0;
  switch (lobe(k)) {
    case DisneyLobe::Diffuse:
    case DisneyLobe::Subsurface: return cosineHemispherePdf(wi.z);
    case DisneyLobe::Specular: return specular_.reflectionPdf(wo, wi);
    case DisneyLobe::Clearcoat: return clearcoat_.reflectionPdf(wo, wi);
  }
  return 0;
}

double DisneyBrdf::pdf(Vec3 wo, Vec3 wi) const {
  if (!(wo.z > 0) || !(wi.z > 0)) return 0;
  return mixturePdf(lobeProbabilities(wo), [&](int k) { return lobePdf(k, wo, wi); });
}

double DisneyBrdf::lobePdf(DisneyLobe lobe, Vec3 wo, Vec3 wi, const Geometry &g, double d) const {
  switch (lobe) {
    case DisneyLobe::Diffuse:
    case DisneyLobe::Subsurface: return cosineHemispherePdf(wi.z);
    case DisneyLobe::Specular: return specular_.reflectionPdfGivenD(wo, d);
    case DisneyLobe::Clearcoat: return clearcoat_.reflectionPdfGivenD(wo, g.h, d);
  }
  return 0;
}

// The half vector and each D computed once for f and pdf; the pdf sums the
// same terms in the same order as pdf(), so the two are equal (tested).
BsdfValue DisneyBrdf::evalWithPdf(Vec3 wo, Vec3 wi) const {
  return evalWithPdf(wo, wi, lobeProbabilities(wo));
}

BsdfValue DisneyBrdf::evalWithPdf(Vec3 wo, Vec3 wi, const LobeProbabilities &p) const {
  const auto g = geometry(wo, wi);
  if (!g) return {Rgb{}, pdf(wo, wi)};  // a direction below the surface: f = 0
  BsdfValue out;
  std::array<double, 4> d{};
  for (int k = 0; k < lobeCount_; ++k) {
    d[k] = microfacetD(lobe(k), g->h);
    if (lobeHasValue_[k]) out.f += lobeValue(lobe(k), wo, wi, *g, d[k]);
  }
  out.pdf = mixturePdf(p, [&](int k) { return lobePdf(lobe(k), wo, wi, *g, d[k]); });
  return out;
}

std::optional<Vec3> DisneyBrdf::sampleLobe(int k, Vec3 wo, Point2 u) const {
  if (!(wo.z > 0) || k < 0 || k >= lobeCount_) return std::nullopt;
  switch (lobe(k)) {
    case DisneyLobe::Diffuse:
    case DisneyLobe::Subsurface: return cosineHemisphere(u);
    case DisneyLobe::Specular: return specular_.sampleReflection(wo, u);
    case DisneyLobe::Clearcoat: return clearcoat_.sampleReflection(wo, u);
  }
  return std::nullopt;
}

std::optional<BsdfSample> DisneyBrdf::sampleChosen(Vec3 wo, const LobeProbabilities &lobeP, int k,
                                                   Point2 u) const {
  const auto wi = sampleLobe(k, wo, u);
  if (!wi || !(wi->z > 0)) return std::nullopt;
  const auto [f, p] = evalWithPdf(wo, *wi, lobeP);
  if (!(p > 0) || !std::isfinite(p) || !f.isFinite()) return std::nullopt;
  return BsdfSample{*wi, f, p, p};
}

std::optional<BsdfSample> DisneyBrdf::sample(Vec3 wo, double uc, Point2 u) const {
  if (!(wo.z > 0)) return std::nullopt;
  const LobeProbabilities lobeP = lobeProbabilities(wo);
  return sampleChosen(wo, lobeP, pickLobe(lobeP, uc).k, u);
}

std::optional<BsdfSample> DisneyBrdf::sampleSquare(Vec3 wo, Point2 u) const {
  if (!(wo.z > 0)) return std::nullopt;
  // u.x chooses the lobe and, rescaled, stays the lobe's first coordinate.
  const LobeProbabilities lobeP = lobeProbabilities(wo);
  const auto [k, ux] = pickLobe(lobeP, u.x);
  return sampleChosen(wo, lobeP, k, {ux, u.y});
}

void DisneyBrdf::hashContent(ContentHash &h) const {
  const DisneyParams &p = params_;
  h.add(name()).add(p.baseColor.r).add(p.baseColor.g).add(p.baseColor.b);
  for (const double v : {p.metallic, p.subsurface, p.specular, p.roughness, p.specularTint,
                         p.anisotropic, p.sheen, p.sheenTint, p.clearcoat, p.clearcoatGloss})
    h.add(v);
  h.add(toString(choice_));
}

}  // namespace nuld
