#pragma once
// The glTF loader's own parts (gltf_loader.cpp, gltf_content.cpp), the two
// translation units that include tinygltf: node transforms, and reading
// materials, textures, cameras and punctual lights from the parsed model.

// Declarations only: Debian's libtinygltf provides the implementation.
#include <tiny_gltf.h>

#include <array>
#include <stdexcept>
#include <string>

#include "materials/vec3.h"
#include "scenes/gltf_loader.h"

namespace nuld::gltf {

[[noreturn]] inline void fail(const std::string &path, const std::string &what) {
  throw std::runtime_error(path + ": " + what);
}

// --- Transforms ----------------------------------------------------------------

// x -> l x + t; l is row-major.
struct Affine {
  std::array<std::array<double, 3>, 3> l = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  Vec3 t;

  Vec3 linear(Vec3 v) const {
    return {l[0][0] * v.x + l[0][1] * v.y + l[0][2] * v.z,
            l[1][0] * v.x + l[1][1] * v.y + l[1][2] * v.z,
            l[2][0] * v.x + l[2][1] * v.y + l[2][2] * v.z};
  }
  Vec3 point(Vec3 p) const { return linear(p) + t; }
  double det() const {
    return l[0][0] * (l[1][1] * l[2][2] - l[1][2] * l[2][1]) -
           l[0][1] * (l[1][0] * l[2][2] - l[1][2] * l[2][0]) +
           l[0][2] * (l[1][0] * l[2][1] - l[1][1] * l[2][0]);
  }
  // The normal matrix: the inverse transpose of l, up to the positive factor
  // |det| (normals are renormalized). The cofactor matrix alone would be off by
  // the sign of det, turning normals inward under a mirror.
  Affine normalMatrix() const {
    Affine n;
    const double s = det() < 0 ? -1.0 : 1.0;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
        n.l[r][c] = s * (l[r1][c1] * l[r2][c2] - l[r1][c2] * l[r2][c1]);
      }
    return n;
  }
};

// a after b.
inline Affine operator*(const Affine &a, const Affine &b) {
  Affine m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      m.l[r][c] = a.l[r][0] * b.l[0][c] + a.l[r][1] * b.l[1][c] + a.l[r][2] * b.l[2][c];
  m.t = a.point(b.t);
  return m;
}

// Sets out.camera from node `index` if it places the file's first
// perspective camera, and adds the punctual light it places (glTF lights
// and cameras shine and look down their node's -z).
void placeCameraAndLight(const std::string &path, const tinygltf::Model &model, int index,
                         const Affine &world, GltfFile &out);

// out.materials, out.textures and the images' names, and out.unused: what
// the file holds beyond what nuld reads.
void readMaterials(const std::string &path, const tinygltf::Model &model, GltfFile &out);

}  // namespace nuld::gltf
