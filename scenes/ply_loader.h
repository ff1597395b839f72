#pragma once
// Stanford PLY triangle meshes (ascii, binary_little_endian, binary_big_endian).
//
// Reads the `vertex` element's x, y, z (any numeric type) and, when all three
// are present, nx, ny, nz (renormalized); and the `face` element's
// `vertex_indices` (or `vertex_index`) list, fan-triangulating polygons. Other
// properties and elements, list-valued ones included, are skipped. The mesh is
// named after the file's stem and has no material.
//
// Errors are std::runtime_error naming the file and what was expected: a bad
// header, truncated data, a non-integer or out-of-range index, a face with
// fewer than 3 vertices, a non-finite position, or a zero-length normal.
// Degenerate triangles are kept.

#include <string>

#include "renderer/triangle_mesh.h"

namespace nuld {

TriangleMesh loadPly(const std::string &path);

}  // namespace nuld
