#pragma once
// What the renderer draws: geometry with one material per mesh, an optional
// environment light and a camera. Scene files build it (scenes/); tests and
// the built-in default scene build it in code.

#include <memory>
#include <optional>
#include <vector>

#include "materials/bsdf.h"
#include "materials/disney.h"
#include "renderer/area_light.h"
#include "renderer/camera.h"
#include "renderer/embree_scene.h"
#include "renderer/environment_light.h"
#include "renderer/light_power.h"
#include "renderer/lobe_tables.h"
#include "renderer/punctual_light.h"
#include "renderer/textured_material.h"

namespace nuld {

// The emitters of a scene beside its environment (area_light.h) and the
// choice among all its lights by power. Empty in a scene without emitters,
// which then builds none of it.
struct SceneLights {
  // Rectangles and spheres: the integrator intersects them itself (they are
  // not in the geometry).
  std::vector<AreaLight> shapes;
  // The triangles of emitting meshes (which are in the geometry): triangle
  // t of mesh m is triangles[meshFirst[m] + t]; meshFirst[m] is kNone for a
  // mesh that does not emit (meshFirst is empty without such meshes).
  std::vector<AreaLight> triangles;
  static constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> meshFirst;
  // Point, spot and directional lights (glTF's punctual lights), which no
  // ray meets.
  std::vector<PunctualLight> punctual;
  // Over shapes, then triangles, then punctual lights, then the environment
  // (last, when the scene has one); set by finishLights().
  std::optional<LightPowerChooser> choice;

  bool empty() const { return areaCount() == 0 && punctual.empty(); }
  std::size_t areaCount() const { return shapes.size() + triangles.size(); }
  std::size_t count() const { return areaCount() + punctual.size(); }
  // Area light i of the choice's numbering (i < areaCount()).
  const AreaLight &light(std::size_t i) const {
    return i < shapes.size() ? shapes[i] : triangles[i - shapes.size()];
  }
  // A direction towards light i of the choice's numbering (i < count())
  // from p, for a uniform u (unused by punctual lights).
  std::optional<AreaLightSample> sample(std::size_t i, Vec3 p, Point2 u) const {
    return i < areaCount() ? light(i).sample(p, u) : punctual[i - areaCount()].sample(p);
  }
};

struct Scene {
  EmbreeScene geometry;
  std::vector<std::shared_ptr<const Bsdf>> materials;  // materials[i] shades mesh i
  std::optional<EnvironmentLight> environment;
  CameraSettings camera;
  // How its Disney materials pick their lobes (each was built with it).
  LobeChoice lobeChoice = kDefaultLobeChoice;
  // The lobe tables its renders build, kept for the next render (only
  // backends that sample lobes ask for them).
  std::shared_ptr<LobeTableCache> lobeTables = std::make_shared<LobeTableCache>();
  // Emitters beside the environment (last: scenes built in code name the
  // members above in order).
  SceneLights lights{};
  // Where a mesh's material varies by textures (glTF): textured[i] for mesh
  // i, or null; empty in a scene without textures. materials[i] is then the
  // same material with the textures' factors alone (what set plans and the
  // lobe tables see).
  std::vector<std::shared_ptr<const TexturedDisney>> textured{};
};

// 16 hex digits of everything a render of the scene depends on beyond its
// render settings: the meshes' positions, normals and triangles, each mesh's
// material (its textures and the meshes' texture coordinates where it has
// any), the environment's texels and sampling, the lights, the camera and
// the lobe choice. Names and file paths are left out: the same content loaded from
// another file or asset root has the same key, and one moved vertex or
// edited material another. Reference caches key by it (backends/
// reference_cache.h). Hashes every byte, about 0.1 s for the dragon.
std::string sceneContentKey(const Scene &scene);

// Makes mesh `mesh` of the scene's geometry an emitter of `radiance`: each
// of its triangles a light (a degenerate one, of zero area, with power 0).
void addEmittingMesh(Scene &scene, std::size_t mesh, Rgb radiance, bool twoSided);
// Builds the choice among the scene's lights by power once its emitters and
// environment are set: each area light's power (AreaLight::power), each
// punctual light's (PunctualLight::power), the environment's pi R^2 times
// its radiant exitance over the sphere (pbrt-v4's infinite lights), R the
// radius of the geometry's bounding sphere. Nothing without emitters.
void finishLights(Scene &scene);

}  // namespace nuld
