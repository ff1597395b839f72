#include "materials/dielectric.h"

#include <algorithm>
#include <cmath>

namespace nuld {

double fresnelDielectric(double cosThetaI, double eta) {
  const double cosI = std::clamp(cosThetaI, 0.0, 1.0);
  const double sin2T = (1 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1) return 1;  // total internal reflection
  const double cosT = std::sqrt(1 - sin2T);
  // s- and p-polarized amplitudes with the near side's index 1.
  const double rs = (cosI - eta * cosT) / (cosI + eta * cosT);
  const double rp = (eta * cosI - cosT) / (eta * cosI + cosT);
  return 0.5 * (rs * rs + rp * rp);
}

std::optional<Vec3> refract(Vec3 w, Vec3 n, double eta) {
  const double cosI = dot(w, n);
  const double sin2T = std::max(0.0, 1 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1) return std::nullopt;
  const double cosT = std::sqrt(1 - sin2T);
  return normalize(-w / eta + (cosI / eta - cosT) * n);
}

double DielectricInterface::reflectProbability(double cosThetaO, double eta) const {
  const double f = fresnelDielectric(cosThetaO, eta);
  return smooth() ? f : std::clamp(f, 0.1, 0.9);
}

DielectricInterface::Value DielectricInterface::eval(Vec3 wo, Vec3 wi, double eta) const {
  if (smooth() || !(wo.z > 0) || wi.z == 0 || !(eta > 0)) return {};
  const double pReflect = reflectProbability(wo.z, eta);
  if (wi.z > 0) {
    const auto h = halfVector(wo, wi);
    if (!h) return {};
    const double dh = d_.D(*h);
    return {dh * fresnelDielectric(dot(wo, *h), eta) * d_.visibility(wo, wi),
            pReflect * d_.reflectionPdfGivenD(wo, dh)};
  }
  // The generalized half vector of a refraction, turned to the near side.
  Vec3 m = wo + eta * wi;
  const double len2 = lengthSquared(m);
  if (!(len2 > 0)) return {};
  m = m / std::sqrt(len2);
  if (m.z < 0) m = -m;
  const double om = dot(wo, m), im = dot(wi, m);
  if (!(om > 0) || !(im < 0)) return {};  // a microfacet seen from behind
  const double denom = (im + om / eta) * (im + om / eta);
  if (!(denom > 0)) return {};
  const Vec3 mirrored{wi.x, wi.y, -wi.z};
  const double dm = d_.D(m);
  const double transmitted = 1 - fresnelDielectric(om, eta);
  const double f = dm * transmitted * d_.G2(wo, mirrored) * std::abs(im * om) /
                   (wo.z * -wi.z * denom) / (eta * eta);
  const double pdf = (1 - pReflect) * d_.visibleD(wo, m) * -im / denom;
  return {f, pdf};
}

std::optional<DielectricInterface::Sample> DielectricInterface::sample(Vec3 wo, double uc, Point2 u,
                                                                       double eta) const {
  if (!(wo.z > 0) || !(eta > 0)) return std::nullopt;
  const double pReflect = reflectProbability(wo.z, eta);
  const bool reflects = uc < pReflect;
  if (smooth()) {
    const double f = fresnelDielectric(wo.z, eta);
    if (reflects) return Sample{{-wo.x, -wo.y, wo.z}, f / wo.z, pReflect, true};
    const auto wi = refract(wo, {0, 0, 1}, eta);
    if (!wi || !(wi->z < 0)) return std::nullopt;
    return Sample{*wi, (1 - f) / (-wi->z * eta * eta), 1 - pReflect, true};
  }
  const Vec3 m = d_.sampleVisibleNormal(wo, u);
  std::optional<Vec3> wi;
  if (reflects) {
    if (const Vec3 r = reflect(wo, m); r.z > 0) wi = r;
  } else if (const auto t = refract(wo, m, eta); t && t->z < 0) {
    wi = t;
  }
  if (!wi) return std::nullopt;
  const Value v = eval(wo, *wi, eta);
  if (!(v.pdf > 0) || !std::isfinite(v.pdf) || !std::isfinite(v.f)) return std::nullopt;
  return Sample{*wi, v.f, v.pdf, false};
}

}  // namespace nuld
