#pragma once
// glTF 2.0 files (.gltf with embedded or external buffers, and .glb): their
// triangle meshes, and for a glTF scene (gltf_scene.h) also their materials,
// textures, first perspective camera and punctual lights.
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
// Read: POSITION (float VEC3), NORMAL (float VEC3) if present, TEXCOORD_0
// (float, or normalized unsigned byte or short, VEC2) if present, and
// indices of any unsigned type, or none. Points and lines are skipped (no
// surface to render); triangle strips and fans, sparse or compressed
// accessors are errors. What nuld does not use (skins, morph targets,
// animations, other textures and extensions) is listed in
// GltfFile::unused.
//
// Errors are std::runtime_error naming the file and what is wrong: a file that
// cannot be opened or parsed (with tinygltf's message), accessors or buffer
// views outside their buffers, an index out of range, a non-finite position, a
// zero-length normal, a node cycle, a material, texture, camera or light
// field out of its range, or no triangles at all.

#include <optional>
#include <string>
#include <vector>

#include "materials/rgb.h"
#include "renderer/punctual_light.h"
#include "renderer/texture.h"
#include "renderer/triangle_mesh.h"

namespace nuld {

// A texture a material reads: an image of the file and its wrap modes.
struct GltfTexture {
  int image = -1;  // into GltfFile::images
  Texture::Wrap wrapU = Texture::Wrap::Repeat, wrapV = Texture::Wrap::Repeat;
};

// An image's encoded bytes (PNG or JPEG), decoded only where a used
// material reads it; `name` names it in messages and says its format.
struct GltfImage {
  std::string name;
  std::vector<unsigned char> bytes;
};

// A metallic-roughness material as the file states it, with the KHR
// extensions nuld maps (gltf_scene.cpp maps it onto the Disney parameters).
struct GltfMaterial {
  std::string name;
  Rgb baseColor{1, 1, 1};
  double alpha = 1, metallic = 1, roughness = 1;
  int baseColorTexture = -1, metallicRoughnessTexture = -1;  // into GltfFile::textures
  Rgb emissive;  // emissiveFactor times KHR_materials_emissive_strength
  // specular: KHR_materials_specular's factor times its colour factor's
  // largest component.
  double transmission = 0, ior = 1.5, clearcoat = 0, clearcoatRoughness = 0, specular = 1;
  bool doubleSided = false;
};

// The first perspective camera a node places: where it is and looks (glTF
// cameras look down their -z with +y up), its vertical field of view and
// its aspect ratio (0 when the file gives none).
struct GltfCamera {
  Vec3 eye, forward, up;
  double yfovRadians = 0, aspectRatio = 0;
};

struct GltfFile {
  std::vector<TriangleMesh> meshes;
  std::vector<int> meshMaterials;  // per mesh, into materials; -1 for none
  std::vector<GltfMaterial> materials;
  std::vector<GltfTexture> textures;
  std::vector<GltfImage> images;
  std::optional<GltfCamera> camera;
  std::vector<PunctualLight> lights;  // KHR_lights_punctual, placed by their nodes
  // What the file holds that nuld does not use, one short phrase each
  // ("2 normal textures", "extension KHR_materials_sheen").
  std::vector<std::string> unused;
};

// Whether `path` names a glTF file (.gltf or .glb, in any case), as the
// loader reads it.
bool isGltfPath(const std::string &path);

// The whole file, images undecoded.
GltfFile loadGltfFile(const std::string &path);
// The meshes alone (a scene file's "meshes" entry), leaving images unread.
std::vector<TriangleMesh> loadGltf(const std::string &path);

}  // namespace nuld
