#pragma once
// What the renderer draws: geometry with one material per mesh, an optional
// environment light and a camera. Scene files build it (scenes/); tests and
// the built-in default scene build it in code.

#include <memory>
#include <optional>
#include <vector>

#include "materials/bsdf.h"
#include "materials/disney.h"
#include "renderer/camera.h"
#include "renderer/embree_scene.h"
#include "renderer/environment_light.h"
#include "renderer/lobe_tables.h"

namespace nuld {

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
};

// 16 hex digits of everything a render of the scene depends on beyond its
// render settings: the meshes' positions, normals and triangles, each mesh's
// material, the environment's texels and sampling, the camera and the lobe
// choice. Names and file paths are left out: the same content loaded from
// another file or asset root has the same key, and one moved vertex or
// edited material another. Reference caches key by it (backends/
// reference_cache.h). Hashes every byte, about 0.1 s for the dragon.
std::string sceneContentKey(const Scene &scene);

}  // namespace nuld
