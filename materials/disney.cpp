#include "materials/disney.h"

#include <algorithm>
#include <cmath>
#include <limits>
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
  check("specTrans", p.specTrans);
  // An index of 1 has no interface to refract at; above 4 is no dielectric.
  if (!(p.ior > 1 && p.ior <= 4))
    throw std::invalid_argument("Disney BRDF: ior = " + std::to_string(p.ior) +
                                " (expected a value in (1, 4])");
}

DisneyBrdf::DisneyBrdf(const DisneyParams &params, LobeChoice choice)
    : params_(validated(params)),
      choice_(choice),
      lobeCount_(params.specTrans > 0   ? 5
                 : params.clearcoat > 0 ? 4
                                        : 3),
      transmission_(params.specTrans > 0),
      diffuseWeight_((1 - params.metallic) * (1 - params.specTrans)),
      specularWeight_(1 - (1 - params.metallic) * params.specTrans),
      transmissionWeight_((1 - params.metallic) * params.specTrans),
      specular_(burleyGgx(params)),
      clearcoat_(lerp(params.clearcoatGloss, 0.1, 0.001)),
      clearcoatMasking_(0.25, 0.25),
      dielectric_(specular_) {
  lobeHasValue_ = {diffuseWeight_ > 0, diffuseWeight_ > 0 && params.subsurface > 0,
                   specularWeight_ > 0, params.clearcoat > 0, transmissionWeight_ > 0};
  onlyDelta_ = transmission_ && dielectric_.smooth() && !lobeHasValue_[0] && !lobeHasValue_[2] &&
               !lobeHasValue_[3];
  const Rgb base = params.baseColor;
  // Tints carry the hue of the base colour, not its brightness. Burley weighs
  // luminance .3/.6/.1; we use Rec. 709 like the rest of the renderer.
  const double lum = base.luminance();
  tint_ = lum > 0 ? base / lum : Rgb::grey(1);
  specular0_ = lerp(params.metallic,
                    params.specular * 0.08 * lerp(params.specularTint, Rgb::grey(1), tint_), base);
  sheenColor_ = lerp(params.sheenTint, Rgb::grey(1), tint_);
  transmissionTint_ = {std::sqrt(base.r), std::sqrt(base.g), std::sqrt(base.b)};
  // Without transmission these are Burley's, bit for bit: the diffuse
  // weight is (1 - metallic) and the specular's 1.
  const double diffuse = diffuseWeight_;
  if (choice == LobeChoice::Weight)
    lobeWeight_ = {diffuse * (1 - params.subsurface), diffuse * params.subsurface, specularWeight_,
                   params.clearcoat / 4, transmissionWeight_};
  else if (choice == LobeChoice::Albedo)
    // The dielectric interface returns nearly all it receives, reflected or
    // refracted, so its estimate is its weight (tinted by what it passes).
    lobeWeight_ = {diffuse * (1 - params.subsurface) * lum, diffuse * params.subsurface * lum,
                   specularWeight_ * specular0_.luminance(), 0.25 * params.clearcoat,
                   transmissionWeight_ * transmissionTint_.luminance()};
}

DisneyBrdf::Side DisneyBrdf::side(Vec3 wo, Vec3 wi) const {
  if (transmission_ && wo.z < 0)
    return {{wo.x, wo.y, -wo.z}, {wi.x, wi.y, -wi.z}, 1 / params_.ior, true};
  return {wo, wi, params_.ior, false};
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
    // coat from its fixed F0 = 0.04. (Seen from inside, the reflection
    // lobes are mirrored to the view's side, as f is.)
    const double fo = schlickWeight(std::clamp(transmission_ ? std::abs(wo.z) : wo.z, 0.0, 1.0));
    estimate[2] = lerp(fo, estimate[2], specularWeight_);
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
                                                                                       Vec3 wi,
                                                                                       double eta) {
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
  g.eta = eta;
  return g;
}

double DisneyBrdf::microfacetD(DisneyLobe lobe, Vec3 h) const {
  switch (lobe) {
    case DisneyLobe::Specular:
    case DisneyLobe::Transmission: return specular_.D(h);
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
      return diffuseWeight_ * ((1 - p.subsurface) * fd * kInvPi * p.baseColor + sheen);
    }
    case DisneyLobe::Subsurface: {
      // Burley's Hanrahan-Krueger-like flattening; the 1/(cos + cos) term
      // lifts grazing response the way thin scattering layers do.
      const double fss90 = p.roughness * cosD2;
      const double fss = (1 + (fss90 - 1) * g.fi) * (1 + (fss90 - 1) * g.fo);
      const double ss = 1.25 * (fss * (1 / (g.cosI + g.cosO) - 0.5) + 0.5);
      return diffuseWeight_ * p.subsurface * ss * kInvPi * p.baseColor;
    }
    case DisneyLobe::Specular: {
      const Rgb fresnel = lerp(g.fd, specular0_, Rgb::grey(1));
      return specularWeight_ * d * specular_.visibility(wo, wi) * fresnel;
    }
    case DisneyLobe::Transmission: {
      // The interface's reflection, white as a dielectric's is; a smooth
      // interface is a delta, with no value at any pair of directions.
      if (dielectric_.smooth()) return {};
      const double fresnel = fresnelDielectric(g.cosD, g.eta);
      return Rgb::grey(transmissionWeight_ * d * fresnel * specular_.visibility(wo, wi));
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
  const Side s = side(wo, wi);
  wo = s.wo, wi = s.wi;
  const auto g = geometry(wo, wi, s.eta);
  if (!g) return transmission_ ? refracted(s, lobeProbabilities(wo)).f : Rgb{};
  Rgb f;
  for (int k = 0; k < lobeCount_; ++k)
    if (lobeHasValue_[k]) f += lobeValue(lobe(k), wo, wi, *g, microfacetD(lobe(k), g->h));
  return f;
}

Rgb DisneyBrdf::evalLobe(int k, Vec3 wo, Vec3 wi) const {
  if (k < 0 || k >= lobeCount_) return {};
  const Side s = side(wo, wi);
  const auto g = geometry(s.wo, s.wi, s.eta);
  if (!g) {
    if (lobe(k) != DisneyLobe::Transmission || !(s.wo.z > 0)) return {};
    return transmissionWeight_ * transmissionTint_ * dielectric_.eval(s.wo, s.wi, s.eta).f;
  }
  return lobeValue(lobe(k), s.wo, s.wi, *g, microfacetD(lobe(k), g->h));
}

double DisneyBrdf::lobePdf(int k, Vec3 wo, Vec3 wi) const {
  if (k < 0 || k >= lobeCount_) return 0;
  const Side s = side(wo, wi);
  wo = s.wo, wi = s.wi;
  if (lobe(k) == DisneyLobe::Transmission) return dielectric_.eval(wo, wi, s.eta).pdf;
  if (!(wo.z > 0) || !(wi.z > 0)) return 0;
  switch (lobe(k)) {
    case DisneyLobe::Diffuse:
    case DisneyLobe::Subsurface: return cosineHemispherePdf(wi.z);
    case DisneyLobe::Specular: return specular_.reflectionPdf(wo, wi);
    case DisneyLobe::Clearcoat: return clearcoat_.reflectionPdf(wo, wi);
    case DisneyLobe::Transmission: break;
  }
  return 0;
}

double DisneyBrdf::pdf(Vec3 wo, Vec3 wi) const {
  const Side s = side(wo, wi);
  if (!(s.wo.z > 0) || !(s.wi.z > 0 || (transmission_ && s.wi.z < 0))) return 0;
  return mixturePdf(lobeProbabilities(wo), [&](int k) { return lobePdf(k, wo, wi); });
}

double DisneyBrdf::lobePdf(DisneyLobe lobe, Vec3 wo, Vec3 wi, const Geometry &g, double d) const {
  switch (lobe) {
    case DisneyLobe::Diffuse:
    case DisneyLobe::Subsurface: return cosineHemispherePdf(wi.z);
    case DisneyLobe::Specular: return specular_.reflectionPdfGivenD(wo, d);
    case DisneyLobe::Clearcoat: return clearcoat_.reflectionPdfGivenD(wo, g.h, d);
    case DisneyLobe::Transmission:
      return dielectric_.smooth() ? 0
                                  : dielectric_.reflectProbability(g.cosO, g.eta) *
                                        specular_.reflectionPdfGivenD(wo, d);
  }
  return 0;
}

// The half vector and each D computed once for f and pdf; the pdf sums the
// same terms in the same order as pdf(), so the two are equal (tested).
BsdfValue DisneyBrdf::evalWithPdf(Vec3 wo, Vec3 wi) const {
  return evalWithPdf(side(wo, wi), lobeProbabilities(wo));
}

BsdfValue DisneyBrdf::refracted(const Side &s, const LobeProbabilities &p) const {
  if (!transmission_ || !(s.wo.z > 0) || !(s.wi.z < 0)) return {};
  const auto v = dielectric_.eval(s.wo, s.wi, s.eta);
  return {transmissionWeight_ * v.f * transmissionTint_, p[int(DisneyLobe::Transmission)] * v.pdf};
}

BsdfValue DisneyBrdf::evalWithPdf(const Side &s, const LobeProbabilities &p) const {
  const Vec3 wo = s.wo, wi = s.wi;
  const auto g = geometry(wo, wi, s.eta);
  if (!g) {  // refracted, or (reflecting only) a direction below the surface: f = 0
    return transmission_ ? refracted(s, p) : BsdfValue{Rgb{}, pdf(wo, wi)};
  }
  BsdfValue out;
  std::array<double, 5> d{};
  for (int k = 0; k < lobeCount_; ++k) {
    d[k] = microfacetD(lobe(k), g->h);
    if (lobeHasValue_[k]) out.f += lobeValue(lobe(k), wo, wi, *g, d[k]);
  }
  out.pdf = mixturePdf(p, [&](int k) { return lobePdf(lobe(k), wo, wi, *g, d[k]); });
  return out;
}

std::optional<Vec3> DisneyBrdf::sampleLobe(int k, Vec3 wo, Point2 u, double uc) const {
  const Side s = side(wo);
  if (!(s.wo.z > 0) || k < 0 || k >= lobeCount_) return std::nullopt;
  std::optional<Vec3> wi;
  switch (lobe(k)) {
    case DisneyLobe::Diffuse:
    case DisneyLobe::Subsurface: wi = cosineHemisphere(u); break;
    case DisneyLobe::Specular: wi = specular_.sampleReflection(s.wo, u); break;
    case DisneyLobe::Clearcoat: wi = clearcoat_.sampleReflection(s.wo, u); break;
    case DisneyLobe::Transmission:
      if (const auto t = dielectric_.sample(s.wo, uc, u, s.eta)) wi = t->wi;
      break;
  }
  if (wi && s.mirrored) wi->z = -wi->z;
  return wi;
}

std::optional<BsdfSample> DisneyBrdf::sampleChosen(const Side &s, const LobeProbabilities &lobeP,
                                                   int k, double uc, Point2 u) const {
  BsdfSample out;
  if (lobe(k) == DisneyLobe::Transmission) {
    const auto t = dielectric_.sample(s.wo, uc, u, s.eta);
    if (!t) return std::nullopt;
    if (t->delta) {
      // The delta's weight; the other lobes have no mass at one direction.
      const double pdf = lobeP[k] * t->pdf;
      if (!(pdf > 0)) return std::nullopt;
      const Rgb tint = t->wi.z < 0 ? transmissionTint_ : Rgb::grey(1);
      out = {t->wi, transmissionWeight_ * t->f * tint, pdf, std::numeric_limits<double>::infinity(),
             true};
    } else {
      const auto [f, p] = evalWithPdf(Side{s.wo, t->wi, s.eta, s.mirrored}, lobeP);
      out = {t->wi, f, p, p};
    }
  } else {
    const auto wi = sampleLobe(k, s.wo, u);  // s.wo is on its own side: no mirror
    if (!wi || !(wi->z > 0)) return std::nullopt;
    const auto [f, p] = evalWithPdf(Side{s.wo, *wi, s.eta, s.mirrored}, lobeP);
    out = {*wi, f, p, p};
  }
  if (!(out.pdf > 0) || !std::isfinite(out.pdf) || !out.f.isFinite()) return std::nullopt;
  if (s.mirrored) out.wi.z = -out.wi.z;
  return out;
}

std::optional<BsdfSample> DisneyBrdf::sample(Vec3 wo, double uc, Point2 u) const {
  const Side s = side(wo);
  if (!(s.wo.z > 0)) return std::nullopt;
  const LobeProbabilities lobeP = lobeProbabilities(wo);
  const auto [k, x] = pickLobe(lobeP, uc);
  return sampleChosen(s, lobeP, k, x, u);
}

std::optional<BsdfSample> DisneyBrdf::sampleSquare(Vec3 wo, Point2 u) const {
  const Side s = side(wo);
  if (!(s.wo.z > 0)) return std::nullopt;
  // u.x chooses the lobe and, rescaled, stays the lobe's first coordinate;
  // in the transmission lobe's stripe it first chooses reflection or
  // refraction, and is rescaled again.
  const LobeProbabilities lobeP = lobeProbabilities(wo);
  auto [k, ux] = pickLobe(lobeP, u.x);
  double uc = 0.5;
  if (lobe(k) == DisneyLobe::Transmission && !dielectric_.smooth()) {
    const double reflect = dielectric_.reflectProbability(s.wo.z, s.eta);
    uc = ux;
    ux = ux < reflect ? ux / reflect : (ux - reflect) / (1 - reflect);
    ux = std::clamp(ux, 0.0, std::nextafter(1.0, 0.0));
  } else if (lobe(k) == DisneyLobe::Transmission) {
    uc = ux;
  }
  return sampleChosen(s, lobeP, k, uc, {ux, u.y});
}

void DisneyBrdf::hashContent(ContentHash &h) const {
  const DisneyParams &p = params_;
  h.add(name()).add(p.baseColor.r).add(p.baseColor.g).add(p.baseColor.b);
  for (const double v : {p.metallic, p.subsurface, p.specular, p.roughness, p.specularTint,
                         p.anisotropic, p.sheen, p.sheenTint, p.clearcoat, p.clearcoatGloss})
    h.add(v);
  // Only a transmitting material adds these, so the keys of every scene
  // cached before transmission existed stay as they were.
  if (transmission_) h.add("transmission").add(p.specTrans).add(p.ior);
  h.add(toString(choice_));
}

}  // namespace nuld
