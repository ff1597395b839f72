#pragma once
// What the renderer draws: geometry with one material per mesh, an optional
// environment light and a camera. Scene files build it (scenes/); tests and
// the built-in default scene build it in code.

#include <memory>
#include <optional>
#include <vector>

#include "materials/bsdf.h"
#include "renderer/camera.h"
#include "renderer/embree_scene.h"
#include "renderer/environment_light.h"

namespace nuld {

struct Scene {
  EmbreeScene geometry;
  std::vector<std::shared_ptr<const Bsdf>> materials;  // materials[i] shades mesh i
  std::optional<EnvironmentLight> environment;
  CameraSettings camera;
};

}  // namespace nuld
