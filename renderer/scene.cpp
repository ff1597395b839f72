#include "renderer/scene.h"

#include <span>

namespace nuld {

namespace {

template <class T>
void addBytes(ContentHash &h, const std::vector<T> &values) {
  h.add(std::uint64_t(values.size()));
  h.add(std::string_view(reinterpret_cast<const char *>(values.data()), values.size() * sizeof(T)));
}

void addVec(ContentHash &h, Vec3 v) { h.add(v.x).add(v.y).add(v.z); }

}  // namespace

std::string sceneContentKey(const Scene &scene) {
  ContentHash h;
  h.add("scene-content-1");
  const std::vector<TriangleMesh> &meshes = scene.geometry.meshes();
  h.add(std::uint64_t(meshes.size()));
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    addBytes(h, meshes[i].positions);
    addBytes(h, meshes[i].normals);
    addBytes(h, meshes[i].triangles);
    if (i < scene.materials.size() && scene.materials[i])
      scene.materials[i]->hashContent(h);
    else
      h.add("no material");
  }
  if (scene.environment)
    scene.environment->hashContent(h);
  else
    h.add("no environment");
  const CameraSettings &c = scene.camera;
  addVec(h, c.eye);
  addVec(h, c.target);
  addVec(h, c.up);
  h.add(c.fovDegrees).add(std::uint64_t(c.mirrorX));
  h.add(toString(scene.lobeChoice));
  return h.hex();
}

}  // namespace nuld
