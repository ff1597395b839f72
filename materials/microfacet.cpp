#include "materials/microfacet.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "materials/sampling.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

// ---------------------------------------------------------------------- GGX

GgxDistribution::GgxDistribution(double alphaX, double alphaY)
    : ax_(std::max(kMinAlpha, alphaX)), ay_(std::max(kMinAlpha, alphaY)) {}

double GgxDistribution::lambda(Vec3 w) const {
  if (!(w.z > 0)) return std::numeric_limits<double>::infinity();
  return 0.5 * (stretchedLength(w) / w.z - 1);
}

double GgxDistribution::G1(Vec3 w) const {
  if (!(w.z > 0)) return 0;
  return 2 * w.z / (w.z + stretchedLength(w));
}

double GgxDistribution::G2(Vec3 wo, Vec3 wi) const {
  if (!(wo.z > 0) || !(wi.z > 0)) return 0;
  // 1 / (1 + L(wo) + L(wi)) with L(w) = (s(w) / w.z - 1) / 2.
  const double so = stretchedLength(wo), si = stretchedLength(wi);
  return 2 * wo.z * wi.z / (so * wi.z + si * wo.z);
}

double GgxDistribution::visibleD(Vec3 wo, Vec3 m) const {
  const double wom = dot(wo, m);
  if (!(wo.z > 0) || !(wom > 0)) return 0;
  // G1(wo) / wo.z = 2 / (wo.z + s(wo)).
  return 2 / (wo.z + stretchedLength(wo)) * wom * D(m);
}

GgxDistribution::VisibleFrame GgxDistribution::visibleFrame(Vec3 wo) const {
  // Stretch the view so that the distribution becomes the hemisphere of
  // roughness 1: visible normals are then uniform on the disc that the
  // hemisphere projects to, seen from vh.
  const Vec3 vh = normalize(Vec3{ax_ * wo.x, ay_ * wo.y, wo.z});
  // A basis around vh; any tangent works at normal incidence.
  const double len2 = vh.x * vh.x + vh.y * vh.y;
  const Vec3 t1 = len2 > 0 ? Vec3{-vh.y, vh.x, 0} / std::sqrt(len2) : Vec3{1, 0, 0};
  return {vh, t1, cross(vh, t1)};
}

Vec3 GgxDistribution::sampleVisibleNormal(Vec3 wo, Point2 u) const {
  const auto [vh, t1, t2] = visibleFrame(wo);
  // A uniform point on the unit disc, then the half of the disc hidden by
  // the hemisphere's silhouette is squeezed into the visible ellipse.
  const double r = std::sqrt(std::clamp(u.x, 0.0, 1.0));
  const SinCos phi = sinCosTurns(u.y);
  const double p1 = r * phi.cos;
  const double s = 0.5 * (1 + vh.z);
  const double p2 = (1 - s) * std::sqrt(std::max(0.0, 1 - p1 * p1)) + s * r * phi.sin;
  // Lift onto the hemisphere, then unstretch (normals transform inversely,
  // which for this diagonal stretch is the same scaling of x and y).
  const Vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1 - p1 * p1 - p2 * p2)) * vh;
  return normalize(Vec3{ax_ * nh.x, ay_ * nh.y, std::max(0.0, nh.z)});
}

double GgxDistribution::reflectionPdf(Vec3 wo, Vec3 wi) const {
  if (!(wo.z > 0) || !(wi.z > 0)) return 0;
  const auto h = halfVector(wo, wi);
  if (!h) return 0;
  // G1(wo) D(h) / (4 wo.z) with G1(wo) / wo.z = 2 / (wo.z + s(wo)).
  return reflectionPdfGivenD(wo, D(*h));
}

std::optional<Vec3> GgxDistribution::sampleReflection(Vec3 wo, Point2 u) const {
  if (!(wo.z > 0)) return std::nullopt;
  const Vec3 wi = reflect(wo, sampleVisibleNormal(wo, u));
  if (!(wi.z > 0)) return std::nullopt;
  return wi;
}

// --------------------------------------------------------------------- GTR1

Gtr1Distribution::Gtr1Distribution(double alpha)
    : alpha_(std::clamp(alpha, GgxDistribution::kMinAlpha, 1.0)) {}

double Gtr1Distribution::D(Vec3 m) const {
  if (!(m.z > 0)) return 0;
  if (alpha_ >= 1) return 1 / kPi;  // the limit of the expression below
  const double a2 = alpha_ * alpha_;
  return (a2 - 1) / (kPi * std::log(a2) * (1 + (a2 - 1) * m.z * m.z));
}

Vec3 Gtr1Distribution::sampleNormal(Point2 u) const {
  // Inverse CDF of cos^2 theta, measured from the pole: 1 - u of the mass
  // lies below cos^2 theta = (1 - a^(2 (1 - u))) / (1 - a^2).
  const double a2 = alpha_ * alpha_;
  const double ux = std::clamp(u.x, 0.0, 1.0);
  const double cos2 =
      alpha_ >= 1 ? 1 - ux : (1 - std::pow(a2, 1 - ux)) / (1 - a2);  // alpha 1: uniform in cos^2
  const double cosTheta = std::sqrt(std::clamp(cos2, 0.0, 1.0));
  const double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
  return sphericalDirectionTurns(sinTheta, cosTheta, u.y);
}

double Gtr1Distribution::reflectionPdf(Vec3 wo, Vec3 wi) const {
  if (!(wo.z > 0) || !(wi.z > 0)) return 0;
  const auto h = halfVector(wo, wi);
  if (!h) return 0;
  return reflectionPdfGivenD(wo, *h, D(*h));
}

double Gtr1Distribution::reflectionPdfGivenD(Vec3 wo, Vec3 h, double dOfH) const {
  const double woh = dot(wo, h);
  if (!(woh > 0)) return 0;
  return dOfH * h.z / (4 * woh);
}

std::optional<Vec3> Gtr1Distribution::sampleReflection(Vec3 wo, Point2 u) const {
  if (!(wo.z > 0)) return std::nullopt;
  const Vec3 m = sampleNormal(u);
  if (!(dot(wo, m) > 0)) return std::nullopt;
  const Vec3 wi = reflect(wo, m);
  if (!(wi.z > 0)) return std::nullopt;
  return wi;
}

}  // namespace nuld
