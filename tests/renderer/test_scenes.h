#pragma once
// Small scenes built in code for the renderer tests.

#include <cmath>
#include <memory>
#include <numbers>

#include "materials/lambertian.h"
#include "renderer/scene.h"

namespace nuld::test {

// A constant-radiance environment map.
inline Image constantMap(float value, int width = 16, int height = 8) {
  return Image{width, height, 3, std::vector<float>(std::size_t(width) * height * 3, value)};
}

// A UV sphere of radius 1 at the origin with smooth normals. It is convex,
// so light that leaves it never returns (white-furnace tests rely on that).
inline TriangleMesh unitSphere(int rings = 24, int segments = 48) {
  TriangleMesh m;
  m.name = "sphere";
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const double th = std::numbers::pi * r / rings, ph = 2 * std::numbers::pi * s / segments;
      const Vec3 n{std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)};
      m.positions.push_back(n);
      m.normals.push_back(n);
    }
  const auto id = [&](int r, int s) { return std::uint32_t(r * (segments + 1) + s); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangles.push_back({id(r, s), id(r, s + 1), id(r + 1, s)});
      m.triangles.push_back({id(r, s + 1), id(r + 1, s + 1), id(r + 1, s)});
    }
  return m;
}

inline Scene sceneWith(std::vector<TriangleMesh> meshes,
                       std::vector<std::shared_ptr<const Bsdf>> materials, std::optional<Image> map,
                       CameraSettings camera = {}) {
  Scene s{EmbreeScene(std::move(meshes)), std::move(materials), std::nullopt, camera};
  if (map) s.environment.emplace(std::move(*map), 1.0, 0.0, "test-map");
  return s;
}

}  // namespace nuld::test
