#pragma once
// Procedural meshes that need no files: the built-in scene, scene files'
// `shape` entries and the tests build their geometry from these.

#include <string>

#include "renderer/triangle_mesh.h"

namespace nuld {

// A UV sphere with smooth normals; the pole rows hold degenerate triangles.
TriangleMesh makeSphere(Vec3 center, double radius, int rings, int segments, std::string name);
// An axis-aligned square in the plane y = height, facing +y.
TriangleMesh makeFloor(double halfSize, double height, std::string name);

}  // namespace nuld
