#include "renderer/area_light.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace nuld {

namespace {

constexpr double kPi = std::numbers::pi;
// pbrt-v4's bounds for sampling by solid angle: below, the spherical map's
// terms cancel in double; above, the rectangle wraps most of a hemisphere.
constexpr double kMinSolidAngle = 3e-4, kMaxSolidAngle = 6.22;

}  // namespace

// The rectangle seen from p in its own frame: x and y along its edges, z
// towards p's far side, p at the origin (z0 < 0 is the plane's offset).
struct AreaLight::SphericalRectangle {
  Vec3 x, y, z;
  double x0, x1, y0, y1, z0;
  double b0, b1, k, solidAngle;
};

AreaLight AreaLight::rectangle(Vec3 corner, Vec3 edge0, Vec3 edge1, Rgb radiance, bool twoSided) {
  AreaLight l;
  l.shape_ = Shape::Rectangle;
  l.p0_ = corner, l.e0_ = edge0, l.e1_ = edge1;
  const Vec3 n = cross(edge0, edge1);
  l.area_ = length(n);
  l.normal_ = n / l.area_;
  l.radiance_ = radiance, l.twoSided_ = twoSided;
  return l;
}

AreaLight AreaLight::sphere(Vec3 centre, double radius, Rgb radiance, bool twoSided) {
  AreaLight l;
  l.shape_ = Shape::Sphere;
  l.p0_ = centre, l.radius_ = radius;
  l.area_ = 4 * kPi * radius * radius;
  l.radiance_ = radiance, l.twoSided_ = twoSided;
  return l;
}

AreaLight AreaLight::triangle(Vec3 a, Vec3 b, Vec3 c, Rgb radiance, bool twoSided) {
  AreaLight l;
  l.shape_ = Shape::Triangle;
  l.p0_ = a, l.e0_ = b - a, l.e1_ = c - a;
  const Vec3 n = cross(l.e0_, l.e1_);
  l.area_ = 0.5 * length(n);
  // A degenerate triangle (a mesh's sliver) has no area and no normal: it
  // has power 0, so it is never chosen, and no sample or pdf of its own.
  l.normal_ = l.area_ > 0 ? n / (2 * l.area_) : Vec3{};
  l.radiance_ = radiance, l.twoSided_ = twoSided;
  return l;
}

double AreaLight::power() const {
  return (twoSided_ ? 2 : 1) * kPi * area_ * radiance_.luminance();
}

Vec3 AreaLight::boundsMin() const {
  if (shape_ == Shape::Sphere) return p0_ - Vec3{radius_, radius_, radius_};
  const Vec3 far = shape_ == Shape::Rectangle ? p0_ + e0_ + e1_ : p0_;
  return min(min(p0_, far), min(p0_ + e0_, p0_ + e1_));
}

Vec3 AreaLight::boundsMax() const {
  if (shape_ == Shape::Sphere) return p0_ + Vec3{radius_, radius_, radius_};
  const Vec3 far = shape_ == Shape::Rectangle ? p0_ + e0_ + e1_ : p0_;
  return max(max(p0_, far), max(p0_ + e0_, p0_ + e1_));
}

void AreaLight::hashContent(ContentHash &h) const {
  for (const Vec3 v : {p0_, e0_, e1_}) h.add(v.x).add(v.y).add(v.z);
  h.add(radius_).add(radiance_.r).add(radiance_.g).add(radiance_.b);
}

Rgb AreaLight::emitted(Vec3 n, Vec3 wi) const {
  return twoSided_ || dot(n, wi) < 0 ? radiance_ : Rgb{};
}

std::optional<AreaLight::Hit> AreaLight::intersect(Vec3 p, Vec3 wi) const {
  if (shape_ == Shape::Sphere) {
    // t^2 - 2 b t + c = 0 with b = wi . (centre - p); the root by the
    // numerically stable form (no cancellation for a far, small sphere).
    const Vec3 d = p0_ - p;
    const double b = dot(wi, d);
    const Vec3 perpendicular = d - b * wi;
    const double disc = radius_ * radius_ - lengthSquared(perpendicular);
    if (disc < 0) return std::nullopt;
    const double root = std::sqrt(disc), c = lengthSquared(d) - radius_ * radius_;
    double t;
    if (c > 0) {  // outside: the near root, b - root = c / (b + root)
      if (b <= 0) return std::nullopt;
      t = c / (b + root);
    } else {  // inside: the far one
      t = b + root;
    }
    if (!(t > 0)) return std::nullopt;
    return Hit{t, normalize(p + t * wi - p0_)};
  }
  const double denom = dot(wi, normal_);
  if (denom == 0) return std::nullopt;
  const double t = dot(p0_ - p, normal_) / denom;
  if (!(t > 0) || !std::isfinite(t)) return std::nullopt;
  const Vec3 q = p + t * wi - p0_;
  // Coordinates along the edges: for the rectangle the projections (the
  // edges are orthogonal), for the triangle barycentrics.
  const double e00 = dot(e0_, e0_), e01 = dot(e0_, e1_), e11 = dot(e1_, e1_);
  const double q0 = dot(q, e0_), q1 = dot(q, e1_);
  const double det = e00 * e11 - e01 * e01;
  const double s = (q0 * e11 - q1 * e01) / det, r = (q1 * e00 - q0 * e01) / det;
  const bool inside = shape_ == Shape::Rectangle ? s >= 0 && s <= 1 && r >= 0 && r <= 1
                                                 : s >= 0 && r >= 0 && s + r <= 1;
  if (!inside) return std::nullopt;
  return Hit{t, normal_};
}

std::optional<AreaLight::SphericalRectangle> AreaLight::subtended(Vec3 p) const {
  SphericalRectangle r;
  const double l0 = length(e0_), l1 = length(e1_);
  r.x = e0_ / l0, r.y = e1_ / l1, r.z = cross(r.x, r.y);
  const Vec3 d = p0_ - p;
  r.x0 = dot(d, r.x), r.y0 = dot(d, r.y), r.z0 = dot(d, r.z);
  if (r.z0 > 0) r.z = -r.z, r.z0 = -r.z0;
  if (!(r.z0 < 0)) return std::nullopt;  // p in the plane: nothing subtended
  r.x1 = r.x0 + l0, r.y1 = r.y0 + l1;
  const Vec3 v00{r.x0, r.y0, r.z0}, v01{r.x0, r.y1, r.z0}, v10{r.x1, r.y0, r.z0},
      v11{r.x1, r.y1, r.z0};
  const Vec3 n0 = normalize(cross(v00, v10)), n1 = normalize(cross(v10, v11)),
             n2 = normalize(cross(v11, v01)), n3 = normalize(cross(v01, v00));
  const auto angle = [](Vec3 a, Vec3 b) { return std::acos(std::clamp(-dot(a, b), -1.0, 1.0)); };
  const double g0 = angle(n0, n1), g1 = angle(n1, n2), g2 = angle(n2, n3), g3 = angle(n3, n0);
  r.b0 = n0.z, r.b1 = n2.z;
  r.k = 2 * kPi - g2 - g3;
  r.solidAngle = g0 + g1 - r.k;
  return r;
}

bool AreaLight::samplesBySolidAngle(const SphericalRectangle &r) const {
  return r.solidAngle >= kMinSolidAngle && r.solidAngle <= kMaxSolidAngle;
}

std::optional<AreaLightSample> AreaLight::towards(Vec3 p, Vec3 q, Vec3 n, double areaPdf) const {
  const Vec3 d = q - p;
  const double dist2 = lengthSquared(d);
  if (!(dist2 > 0) || !std::isfinite(dist2)) return std::nullopt;
  const double dist = std::sqrt(dist2);
  const Vec3 wi = d / dist;
  const double cosLight = std::abs(dot(n, wi));
  if (!(cosLight > 0)) return std::nullopt;
  const double pdf = areaPdf * dist2 / cosLight;
  if (!(pdf > 0) || !std::isfinite(pdf)) return std::nullopt;
  return AreaLightSample{wi, dist, emitted(n, wi), pdf};
}

std::optional<AreaLightSample> AreaLight::sample(Vec3 p, Point2 u) const {
  switch (shape_) {
    case Shape::Rectangle: {
      const auto r = subtended(p);
      if (!r) return std::nullopt;
      if (!samplesBySolidAngle(*r))
        return towards(p, p0_ + u.x * e0_ + u.y * e1_, normal_, 1 / area_);
      // Ureña et al. 2013, section 4: the x of the point from u.x by the
      // area of the spherical rectangle, then y uniform in the height h.
      const double au = u.x * r->solidAngle + r->k;
      const double fu = (std::cos(au) * r->b0 - r->b1) / std::sin(au);
      double cu = std::copysign(1.0, fu) / std::sqrt(fu * fu + r->b0 * r->b0);
      cu = std::clamp(cu, -1.0, 1.0);
      const double xu =
          std::clamp(-(cu * r->z0) / std::max(std::sqrt(1 - cu * cu), 1e-300), r->x0, r->x1);
      const double dd = std::sqrt(xu * xu + r->z0 * r->z0);
      const double h0 = r->y0 / std::sqrt(dd * dd + r->y0 * r->y0),
                   h1 = r->y1 / std::sqrt(dd * dd + r->y1 * r->y1);
      const double hv = h0 + u.y * (h1 - h0), hv2 = hv * hv;
      const double yv =
          hv2 < 1 - 1e-12 ? std::clamp(hv * dd / std::sqrt(1 - hv2), r->y0, r->y1) : r->y1;
      const Vec3 offset = xu * r->x + yv * r->y + r->z0 * r->z;
      const double dist = length(offset);
      if (!(dist > 0)) return std::nullopt;
      const Vec3 wi = offset / dist;
      return AreaLightSample{wi, dist, emitted(normal_, wi), 1 / r->solidAngle};
    }
    case Shape::Sphere: {
      const Vec3 d = p0_ - p;
      const double dc2 = lengthSquared(d);
      if (dc2 <= radius_ * radius_) {
        // Inside: by area over the whole sphere, seen from within.
        const double z = 1 - 2 * u.x, s = std::sqrt(std::max(0.0, 1 - z * z));
        const double phi = 2 * kPi * u.y;
        const Vec3 n{s * std::cos(phi), s * std::sin(phi), z};
        return towards(p, p0_ + radius_ * n, n, 1 / area_);
      }
      // The cone about the centre's direction; sin^2 of its half-angle and
      // 1 - cos, both exact for a tiny or far sphere.
      const double dc = std::sqrt(dc2);
      const Vec3 axis = d / dc;
      const double sin2Max = radius_ * radius_ / dc2;
      const double cosMax = std::sqrt(std::max(0.0, 1 - sin2Max));
      const double oneMinusCosMax = sin2Max / (1 + cosMax);
      const double oneMinusCos = u.x * oneMinusCosMax;
      const double cosTheta = 1 - oneMinusCos;
      const double sin2Theta = std::max(0.0, oneMinusCos * (2 - oneMinusCos));
      const double sinTheta = std::sqrt(sin2Theta), phi = 2 * kPi * u.y;
      // A frame about the axis (Duff et al. 2017's branchless basis).
      const double sign = std::copysign(1.0, axis.z), a = -1 / (sign + axis.z),
                   b = axis.x * axis.y * a;
      const Vec3 t0{1 + sign * axis.x * axis.x * a, sign * b, -sign * axis.x},
          t1{b, sign + axis.y * axis.y * a, -axis.y};
      const Vec3 wi = normalize(sinTheta * std::cos(phi) * t0 + sinTheta * std::sin(phi) * t1 +
                                cosTheta * axis);
      // The near hit of the ray; on the cone's edge the tangent point.
      const auto hit = intersect(p, wi);
      const double dist = hit ? hit->distance : std::sqrt(std::max(0.0, dc2 - radius_ * radius_));
      const Vec3 n = hit ? hit->normal : normalize(p + dist * wi - p0_);
      const double pdf = 1 / (2 * kPi * oneMinusCosMax);
      if (!(pdf > 0) || !std::isfinite(pdf)) return std::nullopt;
      return AreaLightSample{wi, dist, emitted(n, wi), pdf};
    }
    case Shape::Triangle: {
      // Uniform in area: barycentrics by the square-root map.
      const double s = std::sqrt(u.x);
      return towards(p, p0_ + s * (1 - u.y) * e0_ + s * u.y * e1_, normal_, 1 / area_);
    }
  }
  return std::nullopt;
}

double AreaLight::pdf(Vec3 p, Vec3 wi, double *distance) const {
  const auto hit = intersect(p, wi);
  if (!hit) return 0;
  if (distance) *distance = hit->distance;
  const auto byArea = [&] {
    const double cosLight = std::abs(dot(hit->normal, wi));
    return cosLight > 0 ? hit->distance * hit->distance / (cosLight * area_) : 0.0;
  };
  switch (shape_) {
    case Shape::Rectangle: {
      const auto r = subtended(p);
      if (!r) return 0;
      return samplesBySolidAngle(*r) ? 1 / r->solidAngle : byArea();
    }
    case Shape::Sphere: {
      const double dc2 = lengthSquared(p0_ - p);
      if (dc2 <= radius_ * radius_) return byArea();
      const double sin2Max = radius_ * radius_ / dc2;
      const double cosMax = std::sqrt(std::max(0.0, 1 - sin2Max));
      return 1 / (2 * kPi * (sin2Max / (1 + cosMax)));
    }
    case Shape::Triangle: return byArea();
  }
  return 0;
}

}  // namespace nuld
