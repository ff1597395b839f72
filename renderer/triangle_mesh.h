#pragma once
// A triangle mesh as the loaders produce it and the Embree scene consumes it:
// world-space positions, optional per-vertex normals and texture
// coordinates, and the names a scene
// file uses to assign materials.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "materials/vec3.h"
#include "sampler/point.h"

namespace nuld {

struct TriangleMesh {
  std::string name;      // mesh (or node) name from the file
  std::string material;  // material name from the file; empty if none
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // empty, or one unit normal per position
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<Point2> uvs;  // empty, or one texture coordinate per position
};

}  // namespace nuld
