#include "renderer/shapes.h"

#include <cmath>
#include <numbers>

namespace nuld {

TriangleMesh makeSphere(Vec3 center, double radius, int rings, int segments, std::string name) {
  TriangleMesh m;
  m.name = std::move(name);
  for (int r = 0; r <= rings; ++r) {
    const double theta = std::numbers::pi * r / rings;
    for (int s = 0; s <= segments; ++s) {
      const double phi = 2 * std::numbers::pi * s / segments;
      const Vec3 n{std::sin(theta) * std::cos(phi), std::cos(theta),
                   std::sin(theta) * std::sin(phi)};
      m.positions.push_back(center + radius * n);
      m.normals.push_back(n);
    }
  }
  const auto id = [&](int r, int s) { return std::uint32_t(r * (segments + 1) + s); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      // Counter-clockwise seen from outside; the pole rows give degenerate
      // triangles, which the renderer must (and does) cope with.
      m.triangles.push_back({id(r, s), id(r, s + 1), id(r + 1, s)});
      m.triangles.push_back({id(r, s + 1), id(r + 1, s + 1), id(r + 1, s)});
    }
  return m;
}

TriangleMesh makeFloor(double h, double y, std::string name) {
  TriangleMesh m;
  m.name = std::move(name);
  m.positions = {{-h, y, -h}, {h, y, -h}, {h, y, h}, {-h, y, h}};
  m.normals.assign(4, Vec3{0, 1, 0});
  m.triangles = {{0, 2, 1}, {0, 3, 2}};
  return m;
}

}  // namespace nuld
