#pragma once
// Scene files: JSON naming meshes (glTF, PLY) by path under an asset root,
// Disney or Lambertian materials by the meshes' material or mesh names, the
// camera, an environment map and default render settings. The built-in scene
// `default` needs no files at all.
//
//   {
//     "camera":      {"eye": [x,y,z], "look_at": [x,y,z], "up": [0,1,0], "fov": 37,
//                     "mirror_x": false},
//     "film":        {"width": 512, "height": 512},
//     "render":      {"spp": 64, "integrator": "path", "max_depth": 5,
//                     "backend": "sobol", "seed": 1},
//     "environment": {"file": "envmaps/grace_latlong.exr", "scale": 1, "rotation": 0,
//                     "up": [0,1,0], "importance": "luminance-compensated"},
//     "materials":   {"OuterMat": {"type": "disney", "base_color": [.9,.9,.9],
//                                  "metallic": 1, "roughness": .2}, ...},
//     "meshes":      [{"file": "lte_orb/lte_orb.glb", "skip": ["Material"]},
//                     {"file": "cup/geometry_mesh_00002.ply", "material": "floor",
//                      "transform": {"scale": 1, "rotate_y": 0, "translate": [0,0,0]}},
//                     {"shape": "floor", "half_size": 20, "height": 0, "material": "floor"},
//                     {"shape": "sphere", "center": [0,1,0], "radius": 1,
//                      "emission": {"radiance": [1,1,1], "scale": 1, "two_sided": false}}],
//     "emitters":    [{"shape": "rectangle", "corner": [x,y,z], "edge0": [..], "edge1": [..],
//                      "radiance": [r,g,b], "scale": 1, "two_sided": false},
//                     {"shape": "sphere", "center": [x,y,z], "radius": r, "radiance": 10}]
//   }
//
// A mesh gets the entry's "material" if given, else the material named like
// its file material, else the one named like the mesh, else "default"; with
// none of these the loader stops and names the mesh. The environment's
// "rotation" turns the map about its zenith (degrees) and "up" is the world
// direction of its zenith (row 0; renderer/environment_light.h): a map stored
// upside down takes [0,-1,0]. "importance" weighs a texel's sampling
// density by its luminance ("luminance", the supplement's target) or by the
// mean of its channels ("mean"), either less the map's mean over the sphere
// ("-compensated": MIS compensation, the default, kDefaultImportance). A
// scene builds only what
// it uses: unused materials are never instantiated, without an
// "environment" no map is read, and without emitters no light choice is
// built. A rectangle emits on the side of cross(edge0, edge1), its edges
// orthogonal; an "emission" makes each triangle of the entry's meshes a
// light (renderer/area_light.h); radiance is finite and >= 0.
//
// A .gltf or .glb path is a scene of its own (gltf_scene.h); a scene file's
// "gltf": "FILE.glb" takes its meshes, materials, lights and camera from
// it, and then refuses "meshes" and "materials" (its own "camera" and
// "film" replace the file's).

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend_registry.h"
#include "renderer/render.h"
#include "renderer/scene.h"

namespace nuld {

// A scene's environment importance when its file names none (and the
// built-in scenes'): the map's luminance less its mean, the stronger classic
// light sampler under MIS (tools/experiments/env_compensation.md has the
// figures). The light integrator samples such a map without the compensation
// (sampledLight).
inline constexpr PixelWeight kDefaultImportance = PixelWeight::LuminanceCompensated;

// What a command chooses for a whole scene beyond its file: how its Disney
// materials pick a lobe (materials/disney.h) and, when given, the
// environment's importance in place of the file's (the built-in scenes have
// no file to name one). The paper's configuration is {Uniform, Luminance}.
struct SceneChoices {
  SceneChoices(LobeChoice lobes = kDefaultLobeChoice,
               std::optional<PixelWeight> importance = std::nullopt)
      : lobes(lobes), importance(importance) {}
  LobeChoice lobes;
  std::optional<PixelWeight> importance;
};

struct LoadedScene {
  std::string name;  // file path, or "default"
  Scene scene;
  RenderSettings settings;  // the file's defaults; the CLI may override them
  std::string backend = "sobol";
  std::uint64_t seed = kDefaultSeed;  // "seed" of the file, else the common default
};

// The asset root: `explicitRoot` if not empty, else $NULD_ASSETS, else
// shared/assets beside the checkout (../shared/assets from the source tree).
std::string resolveAssetRoot(const std::string &explicitRoot);

// The built-in scenes, which need no files and no asset root: default,
// stress (default_scene.h), cornell (cornell_scene.h) and veach-mis
// (veach_mis_scene.h); and the same as "default, stress, ..." for help texts.
const std::vector<std::string> &builtInScenes();
std::string builtInSceneList();
bool isBuiltInScene(const std::string &name);

// `path` is a JSON scene file or a built-in scene's name. Throws std::invalid_argument or
// std::runtime_error naming the file, the field and what was expected.
// `choices` set its materials' lobe choice and may override its
// environment's importance.
LoadedScene loadScene(const std::string &path, const std::string &assetRoot,
                      const SceneChoices &choices = {});

}  // namespace nuld
