#pragma once
// Triangle meshes in an Embree 3 BVH. Embree's handles are wrapped in RAII
// types so a scene can be moved and destroyed like any value; the meshes are
// kept for shading (vertex normals) after Embree has built its BVH.

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "materials/vec3.h"
#include "renderer/triangle_mesh.h"

namespace nuld {

struct Ray {
  Vec3 origin, direction;
  double tMax = std::numeric_limits<double>::infinity();
};

struct SurfaceHit {
  double t = 0;
  Vec3 position;
  Vec3 geometricNormal;  // unit, as Embree's winding gives it
  Vec3 shadingNormal;    // unit, interpolated vertex normals (or the geometric one)
  // From `position` to the shading position: the barycentric blend of the
  // position's projections on the three vertex tangent planes (Hanika 2021,
  // "Hacking the shadow terminator"), which lies on the smooth surface the
  // vertex normals describe. Zero on a flat-shaded mesh. Rays leave from
  // there (path_integrator.cpp), so that a direction above the shading
  // hemisphere but below the flat triangle escapes a convex patch as it
  // would the smooth surface.
  Vec3 shadingOffset;
  // The texture coordinates interpolated at `position`; (0, 0) on a mesh
  // without any.
  Point2 uv;
  std::uint32_t mesh = 0, triangle = 0;
};

class EmbreeScene {
 public:
  explicit EmbreeScene(std::vector<TriangleMesh> meshes);
  ~EmbreeScene();
  EmbreeScene(EmbreeScene &&) noexcept;
  EmbreeScene &operator=(EmbreeScene &&) noexcept;

  std::optional<SurfaceHit> intersect(const Ray &ray) const;
  // The closest hits of several rays that start close together and point in
  // nearly the same direction (the camera rays of neighbouring pixels),
  // traced as packets of 16: Embree walks such a packet several times faster
  // per ray than one ray at a time. hits[k] is the hit of rays[k], the same
  // hit intersect() finds up to float rounding; any rays are accepted.
  void intersectCoherent(std::span<const Ray> rays,
                         std::span<std::optional<SurfaceHit>> hits) const;
  // The closest hits of several unrelated rays (a packet's bounce rays),
  // one rtcIntersect1 each; the same hits as intersect(). The meshes' data
  // of all hits is fetched before any hit is built, so on a large mesh their
  // cache misses overlap instead of following one another.
  void intersect(std::span<const Ray> rays, std::span<std::optional<SurfaceHit>> hits) const;
  // True when anything blocks the segment (origin, origin + tMax * direction).
  bool occluded(const Ray &ray) const;

  const std::vector<TriangleMesh> &meshes() const { return meshes_; }
  std::size_t triangleCount() const;

  // The raw Embree query, for the benchmark that compares the renderer with
  // Embree alone: returns the hit distance or infinity.
  float rawIntersect(const float origin[3], const float direction[3]) const;

 private:
  // What a hit is from Embree's answer (mesh, triangle, barycentrics, t);
  // nullopt when the answer is a miss (Embree's invalid geometry id).
  std::optional<SurfaceHit> surfaceHit(const Ray &ray, float t, unsigned mesh, unsigned triangle,
                                       float u, float v) const;

  struct Handles;
  std::unique_ptr<Handles> handles_;
  std::vector<TriangleMesh> meshes_;
};

// Moves a ray origin off the surface along the geometric normal, on the side
// of `direction`, by an offset that scales with the coordinates' magnitude
// (Embree intersects in single precision).
Vec3 offsetRayOrigin(Vec3 p, Vec3 geometricNormal, Vec3 direction);

}  // namespace nuld
