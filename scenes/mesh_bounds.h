#pragma once
// Axis-aligned bounds of loaded meshes: scene files and tests use them to
// place cameras and floors, and to check that an asset is where it should be.

#include <limits>
#include <span>

#include "renderer/triangle_mesh.h"

namespace nuld {

struct MeshBounds {
  // Starts inverted so that the first point sets both corners.
  Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  Vec3 hi = -lo;

  bool empty() const { return lo.x > hi.x; }
  void extend(Vec3 p) {
    lo = min(lo, p);
    hi = max(hi, p);
  }
  void extend(const MeshBounds &b) {
    lo = min(lo, b.lo);
    hi = max(hi, b.hi);
  }
};

// Bounds of all positions, referenced by a triangle or not.
inline MeshBounds meshBounds(const TriangleMesh &mesh) {
  MeshBounds b;
  for (const Vec3 &p : mesh.positions) b.extend(p);
  return b;
}

inline MeshBounds meshBounds(std::span<const TriangleMesh> meshes) {
  MeshBounds b;
  for (const TriangleMesh &m : meshes) b.extend(meshBounds(m));
  return b;
}

}  // namespace nuld
