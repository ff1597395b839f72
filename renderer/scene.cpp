#include "renderer/scene.h"

#include <numbers>
#include <span>

namespace nuld {

namespace {

constexpr double kPi = std::numbers::pi;

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
    // Only a textured mesh adds its coordinates and textures: every other
    // key stays as it was.
    if (i < scene.textured.size() && scene.textured[i]) {
      addBytes(h, meshes[i].uvs);
      scene.textured[i]->hashContent(h);
    }
  }
  if (scene.environment)
    scene.environment->hashContent(h);
  else
    h.add("no environment");
  // Only a scene with emitters adds them: every other key stays as it was.
  if (!scene.lights.empty()) {
    h.add("area-lights-1");
    for (const std::vector<AreaLight> *lights : {&scene.lights.shapes, &scene.lights.triangles})
      for (const AreaLight &l : *lights) {
        h.add(std::uint64_t(l.shape())).add(std::uint64_t(l.twoSided()));
        l.hashContent(h);
      }
    for (const PunctualLight &l : scene.lights.punctual) l.hashContent(h);
  }
  const CameraSettings &c = scene.camera;
  addVec(h, c.eye);
  addVec(h, c.target);
  addVec(h, c.up);
  h.add(c.fovDegrees).add(std::uint64_t(c.mirrorX));
  h.add(toString(scene.lobeChoice));
  return h.hex();
}

void addEmittingMesh(Scene &scene, std::size_t mesh, Rgb radiance, bool twoSided) {
  const TriangleMesh &m = scene.geometry.meshes().at(mesh);
  SceneLights &lights = scene.lights;
  if (lights.meshFirst.size() < scene.geometry.meshes().size())
    lights.meshFirst.resize(scene.geometry.meshes().size(), SceneLights::kNone);
  lights.meshFirst[mesh] = std::uint32_t(lights.triangles.size());
  for (const auto &t : m.triangles)
    lights.triangles.push_back(AreaLight::triangle(m.positions[t[0]], m.positions[t[1]],
                                                   m.positions[t[2]], radiance, twoSided));
}

void finishLights(Scene &scene) {
  SceneLights &lights = scene.lights;
  if (lights.empty()) return;
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const TriangleMesh &m : scene.geometry.meshes())
    for (const Vec3 p : m.positions) lo = min(lo, p), hi = max(hi, p);
  for (const AreaLight &l : lights.shapes) lo = min(lo, l.boundsMin()), hi = max(hi, l.boundsMax());
  const double radius = 0.5 * length(hi - lo);
  std::vector<double> powers;
  for (std::size_t i = 0; i < lights.areaCount(); ++i) powers.push_back(lights.light(i).power());
  for (const PunctualLight &l : lights.punctual) powers.push_back(l.power(radius));
  if (scene.environment && scene.environment->target()) {
    // Radiant exitance of the sphere's inside: pi times its mean radiance.
    powers.push_back(kPi * radius * radius * kPi * 4 * scene.environment->meanLuminance());
  }
  lights.choice.emplace(powers);
}

}  // namespace nuld
