#pragma once
// glTF 2.0 triangle meshes (.gltf with embedded or external buffers, and .glb).
//
// Walks the default scene (scene 0 when none is marked; every root node when
// the file has no scenes) and returns one world-space TriangleMesh per mesh
// primitive per node instance: node transforms (matrix or TRS) are applied to
// positions, their inverse transpose to normals (renormalized), and the winding
// is flipped under a mirroring transform so that it stays counter-clockwise.
// A node whose transform is singular (zero scale, used to hide things) adds
// nothing, nor does a primitive without triangles. The mesh is named after the
// glTF mesh, else its node, else "mesh<index>"; the material is the glTF
// material's name, "" when it has none.
//
// Read: POSITION (float VEC3), NORMAL (float VEC3) if present, and indices of
// any unsigned type, or none. Points and lines are skipped (no surface to
// render); triangle strips and fans, sparse or compressed accessors are errors.
// Skins, morph targets, textures and cameras are ignored.
//
// Errors are std::runtime_error naming the file and what is wrong: a file that
// cannot be opened or parsed (with tinygltf's message), accessors or buffer
// views outside their buffers, an index out of range, a non-finite position, a
// zero-length normal, a node cycle, or no triangles at all.

#include <string>
#include <vector>

#include "renderer/triangle_mesh.h"

namespace nuld {

std::vector<TriangleMesh> loadGltf(const std::string &path);

}  // namespace nuld
