#pragma once
// Emitters on shapes, beside the environment (renderer/README.md,
// `area_light`): a rectangle, a sphere or a triangle of a mesh, emitting a
// constant radiance, one-sided (the side its normal faces) unless made
// two-sided. Next-event estimation samples each by solid angle where the
// field does, and pdf() gives the same density for a direction a BSDF
// sample drew, so the two strategies combine by MIS:
//  - a rectangle by the spherical rectangle it subtends (Ureña, Fajardo and
//    King 2013), uniform in solid angle;
//  - a sphere by the cone it subtends (pbrt-v4), uniform in solid angle,
//    with the small-angle forms that keep a tiny or far sphere exact;
//  - a triangle by area, its density converted to solid angle. Spherical
//    triangle sampling (Arvo 1995) loses its precision on the small and far
//    triangles a mesh emitter is made of (pbrt-v4 falls back to area there
//    too), and area sampling is exact for any of them.
// A rectangle that subtends almost nothing, or nearly a hemisphere, is
// sampled by area as well (pbrt-v4's bounds), where the spherical map's
// arithmetic would cancel; pdf() follows the same choice, which depends on
// the shading point only.

#include <optional>

#include "materials/rgb.h"
#include "materials/vec3.h"
#include "sampler/io/content_hash.h"
#include "sampler/point.h"

namespace nuld {

// A direction towards an emitter from a shading point.
struct AreaLightSample {
  Vec3 wi;          // unit, from the shading point towards the light
  double distance;  // to the point sampled on the light
  Rgb radiance;     // emitted towards the shading point (0 from its back)
  double pdf;       // per unit solid angle, > 0; 1 for a delta light
  // From a light of no extent (punctual_light.h): no BSDF sample can draw
  // wi, so the light sample's MIS weight is 1.
  bool delta = false;
};

class AreaLight {
 public:
  enum class Shape { Rectangle, Sphere, Triangle };

  // The parallelogram corner + s edge0 + t edge1 (s, t in [0, 1]), its edges
  // orthogonal (a rectangle; checked by the scene parser); it faces
  // cross(edge0, edge1).
  static AreaLight rectangle(Vec3 corner, Vec3 edge0, Vec3 edge1, Rgb radiance,
                             bool twoSided = false);
  // Emits outwards (twoSided: inwards too, for a point inside it).
  static AreaLight sphere(Vec3 centre, double radius, Rgb radiance, bool twoSided = false);
  // Faces cross(b - a, c - a), as a mesh's winding gives its normal.
  static AreaLight triangle(Vec3 a, Vec3 b, Vec3 c, Rgb radiance, bool twoSided = false);

  Shape shape() const { return shape_; }
  // A rectangle's or triangle's unit normal (the side it emits from).
  Vec3 normal() const { return normal_; }
  double area() const { return area_; }
  Rgb radiance() const { return radiance_; }
  bool twoSided() const { return twoSided_; }
  // The luminance of the flux it emits, pi A L (2 pi A L two-sided): what
  // choosing lights by power weighs (light_power.h).
  double power() const;

  // The corners of a box around it.
  Vec3 boundsMin() const;
  Vec3 boundsMax() const;
  // Adds its geometry and radiance to `h` (the scene's content key).
  void hashContent(ContentHash &h) const;

  // A direction towards the light from `p` for a uniform `u`; none when `p`
  // sees none of it (on its plane). Seen from behind a one-sided light the
  // sample carries no radiance (its pdf stays what pdf() says).
  std::optional<AreaLightSample> sample(Vec3 p, Point2 u) const;
  // The density sample() has of drawing `wi` (unit) from `p`, per unit solid
  // angle; 0 when the ray misses the light. `distance`, if given, gets the
  // distance to the light along wi.
  double pdf(Vec3 p, Vec3 wi, double *distance = nullptr) const;
  // The radiance leaving the light at a point whose outward normal is `n`
  // towards the direction -wi (wi pointing at the light).
  Rgb emitted(Vec3 n, Vec3 wi) const;
  // The same for a rectangle or triangle, whose normal is its own.
  Rgb emittedTowards(Vec3 wi) const { return emitted(normal_, wi); }
  // The distance along the ray p + t wi (unit wi) to the light, and its
  // outward normal there; none on a miss.
  struct Hit {
    double distance;
    Vec3 normal;
  };
  std::optional<Hit> intersect(Vec3 p, Vec3 wi) const;

 private:
  AreaLight() = default;
  // The spherical rectangle's frame seen from p (Ureña et al. 2013, section
  // 3), and its solid angle; none when p lies in the rectangle's plane.
  struct SphericalRectangle;
  std::optional<SphericalRectangle> subtended(Vec3 p) const;
  bool samplesBySolidAngle(const SphericalRectangle &r) const;
  std::optional<AreaLightSample> towards(Vec3 p, Vec3 q, Vec3 n, double areaPdf) const;

  Shape shape_ = Shape::Rectangle;
  Vec3 p0_, e0_, e1_, normal_;  // corner and edges, or the triangle's a, b - a, c - a
  double radius_ = 0, area_ = 0;
  Rgb radiance_;
  bool twoSided_ = false;
};

}  // namespace nuld
