// glTF files as whole scenes (scenes/gltf_scene.h), on the scene the
// project's own script writes (tools/gltf/make_test_scene.py): its nodes,
// camera, materials mapped onto the Disney parameters, textures, emissive
// and punctual lights, the note of what is not used, .gltf and .glb alike,
// a scene file naming it, and malformed files refused naming the field.
#include "scenes/gltf_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "backends/backend_registry.h"
#include "renderer/render.h"
#include "sampler/diagnostics.h"
#include "scenes/scene_file.h"
#include "tests/common/expect_error.h"
#include "tests/common/temp_dir.h"

namespace nuld {
namespace {

using test::TempDir;
using json = nlohmann::json;

// The test scene written by the project's script into `dir`.
std::string writeScene(const TempDir &dir, const std::string &name,
                       const std::string &lights = "all") {
  const std::string out = (dir / name).string();
  const std::string command = "/usr/bin/python3 " NULD_SOURCE_DIR
                              "/tools/gltf/make_test_scene.py '" +
                              out + "' --lights " + lights;
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return out;
}

// The scene and every warning its loading gave.
LoadedScene loadNoting(const std::string &path, std::vector<std::string> &warnings) {
  const WarningHandler previous =
      setWarningHandler([&](const std::string &m) { warnings.push_back(m); });
  LoadedScene scene = loadScene(path, "");
  setWarningHandler(previous);
  return scene;
}

const DisneyBrdf &disneyOf(const Scene &scene, const std::string &mesh) {
  const auto &meshes = scene.geometry.meshes();
  for (std::size_t i = 0; i < meshes.size(); ++i)
    if (meshes[i].name == mesh) return dynamic_cast<const DisneyBrdf &>(*scene.materials[i]);
  ADD_FAILURE() << "no mesh " << mesh;
  throw std::logic_error("no such mesh");
}

std::size_t meshIndex(const Scene &scene, const std::string &mesh) {
  const auto &meshes = scene.geometry.meshes();
  for (std::size_t i = 0; i < meshes.size(); ++i)
    if (meshes[i].name == mesh) return i;
  return meshes.size();
}

TEST(GltfScene, MapsTheTestScene) {
  TempDir dir;
  std::vector<std::string> warnings;
  const LoadedScene loaded = loadNoting(writeScene(dir, "scene.gltf"), warnings);
  const Scene &scene = loaded.scene;
  EXPECT_EQ(scene.geometry.meshes().size(), 6u);
  // The camera node's place and view; aspect 1.5 sets the film.
  EXPECT_NEAR(scene.camera.eye.y, 1.6, 1e-6);
  EXPECT_NEAR(scene.camera.eye.z, 4.2, 1e-6);
  const Vec3 view = normalize(scene.camera.target - scene.camera.eye);
  const Vec3 wanted = normalize(Vec3{0, 0.45, 0} - Vec3{0, 1.6, 4.2});
  EXPECT_GT(dot(view, wanted), 1 - 1e-9);
  EXPECT_NEAR(scene.camera.fovDegrees, 0.75 * 180 / std::numbers::pi, 1e-9);
  EXPECT_EQ(loaded.settings.width, 512);
  EXPECT_EQ(loaded.settings.height, 341);
  // The box is placed through its parent: scaled by 0.8, its base on the floor.
  const TriangleMesh &box = scene.geometry.meshes()[meshIndex(scene, "box")];
  double lowest = 1e9, highest = -1e9;
  for (const Vec3 &p : box.positions)
    lowest = std::min(lowest, p.y), highest = std::max(highest, p.y);
  EXPECT_NEAR(lowest, 0, 1e-6);
  EXPECT_NEAR(highest, 0.8, 1e-6);

  // Materials.
  const DisneyParams glass = disneyOf(scene, "glass-slab").params();
  EXPECT_EQ(glass.specTrans, 1);
  EXPECT_EQ(glass.ior, 1.5);
  EXPECT_EQ(glass.roughness, 0);
  const DisneyParams coat = disneyOf(scene, "coated-ball").params();
  EXPECT_EQ(coat.clearcoat, 1);
  EXPECT_NEAR(coat.clearcoatGloss, (0.1 - 0.01) / 0.099, 1e-12);
  EXPECT_NEAR(coat.specular, 0.8 * 0.5, 1e-12);  // ior 1.5's F0 0.04 is specular 0.5
  const DisneyParams clay = disneyOf(scene, "box").params();
  EXPECT_NEAR(clay.baseColor.r, 0.8, 1e-12);
  EXPECT_EQ(clay.metallic, 0);
  EXPECT_NEAR(clay.roughness, 0.6, 1e-12);
  // Textures on the floor and the metal ball only.
  ASSERT_EQ(scene.textured.size(), scene.geometry.meshes().size());
  const std::size_t floor = meshIndex(scene, "floor"), metal = meshIndex(scene, "metal-ball");
  for (std::size_t i = 0; i < scene.textured.size(); ++i)
    EXPECT_EQ(bool(scene.textured[i]), i == floor || i == metal) << i;
  // The checker's 204 of 255, decoded from sRGB.
  const Texture &checker = *scene.textured[floor]->baseColor;
  EXPECT_NEAR(checker.texel(0, 0).g, srgbToLinear(204 / 255.0), 1e-6);
  EXPECT_NEAR(checker.texel(0, 0).g, 0.6038, 1e-4);
  // The metal-roughness texture is linear: texel (1, 0) holds G 255, B 255.
  EXPECT_NEAR(scene.textured[metal]->metallicRoughness->texel(1, 0).g, 1.0, 1e-6);

  // Lights: the emissive panel's two triangles, three punctual lights.
  EXPECT_EQ(scene.lights.triangles.size(), 2u);
  EXPECT_NEAR(scene.lights.triangles[0].radiance().r, 8.0, 1e-12);
  EXPECT_EQ(scene.lights.punctual.size(), 3u);
  ASSERT_TRUE(scene.lights.choice);
  EXPECT_EQ(scene.lights.choice->size(), 5u);

  // One note names what is not used.
  ASSERT_EQ(warnings.size(), 1u);
  for (const char *part :
       {"not used by nuld", "normal textures (1)",
        "materials with extension KHR_materials_sheen (1)", "an orthographic camera"})
    EXPECT_NE(warnings[0].find(part), std::string::npos) << part << " in " << warnings[0];
}

TEST(GltfScene, GltfAndGlbAreTheSameScene) {
  TempDir dir;
  std::vector<std::string> ignored;
  const LoadedScene a = loadNoting(writeScene(dir, "scene.gltf"), ignored);
  const LoadedScene b = loadNoting(writeScene(dir, "scene.glb"), ignored);
  EXPECT_EQ(sceneContentKey(a.scene), sceneContentKey(b.scene));
}

// Each kind of light alone lights the scene, and no pixel is NaN.
TEST(GltfScene, EveryLightRendersFinite) {
  TempDir dir;
  for (const std::string lights : {"point", "spot", "directional", "emissive"}) {
    std::vector<std::string> ignored;
    const LoadedScene loaded = loadNoting(writeScene(dir, lights + ".glb", lights), ignored);
    RenderSettings s{48, 32, 4, IntegratorKind::Path, 6, 2};
    auto backend = makeBackend("sobol", 1);
    RenderStats stats;
    const Image img = render(loaded.scene, s, *backend, &stats);
    EXPECT_EQ(stats.rejectedSamples, 0u) << lights;
    double sum = 0;
    for (const float v : img.pixels) {
      ASSERT_TRUE(std::isfinite(v)) << lights;
      sum += v;
    }
    EXPECT_GT(sum, 0) << lights;
  }
}

TEST(GltfScene, SceneFileAddsSettingsAndEnvironment) {
  TempDir dir;
  writeScene(dir, "scene.glb");
  const std::string file = dir.write("scene.json", R"({
    "gltf": "scene.glb",
    "film": {"width": 64, "height": 32},
    "render": {"spp": 8, "integrator": "direct"},
    "camera": {"eye": [0, 3, 5], "look_at": [0, 0, 0], "fov": 30}
  })");
  std::vector<std::string> ignored;
  const WarningHandler previous =
      setWarningHandler([&](const std::string &m) { ignored.push_back(m); });
  const LoadedScene loaded = loadScene(file, dir.path().string());
  setWarningHandler(previous);
  EXPECT_EQ(loaded.settings.width, 64);
  EXPECT_EQ(loaded.settings.spp, 8u);
  EXPECT_EQ(loaded.scene.camera.fovDegrees, 30);
  EXPECT_EQ(loaded.scene.geometry.meshes().size(), 6u);
  const std::string both = dir.write("both.json", R"({"gltf": "scene.glb", "meshes": []})");
  const std::string message = test::errorMessage([&] { loadScene(both, dir.path().string()); });
  EXPECT_NE(message.find("'meshes'"), std::string::npos) << message;
  const std::string missing = dir.write("missing.json", R"({"gltf": "nothing.glb"})");
  const std::string why =
      test::errorMessage<std::runtime_error>([&] { loadScene(missing, dir.path().string()); });
  EXPECT_NE(why.find("nothing.glb' does not exist"), std::string::npos) << why;
}

// Malformed fields are refused naming the file and the field.
TEST(GltfScene, MalformedFieldsNameTheField) {
  TempDir dir;
  const std::string good = writeScene(dir, "scene.gltf");
  const json doc = json::parse(std::ifstream(good));
  const auto broken = [&](const std::string &name, const std::function<void(json &)> &edit) {
    json d = doc;
    edit(d);
    return test::errorMessage<std::runtime_error>(
        [&] { loadScene(dir.write(name, d.dump()), ""); });
  };
  const auto expectIn = [](const std::string &message, const std::string &part) {
    EXPECT_NE(message.find(part), std::string::npos) << part << " not in: " << message;
  };
  expectIn(
      broken("rough.gltf",
             [](json &d) { d["materials"][1]["pbrMetallicRoughness"]["roughnessFactor"] = 2; }),
      "rough.gltf: material 1 ('clay') roughnessFactor");
  expectIn(broken("tex.gltf",
                  [](json &d) {
                    d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 9;
                  }),
           "names texture 9, which does not exist");
  expectIn(
      broken("ior.gltf",
             [](json &d) { d["materials"][3]["extensions"]["KHR_materials_ior"]["ior"] = 1.0; }),
      "KHR_materials_ior.ior must be in (1, 4]");
  expectIn(
      broken(
          "strength.gltf",
          [](json &d) {
            d["materials"][5]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] =
                -1;
          }),
      "KHR_materials_emissive_strength.emissiveStrength");
  expectIn(
      broken("light.gltf",
             [](json &d) { d["extensions"]["KHR_lights_punctual"]["lights"][0]["type"] = "area"; }),
      "light 0 ('') type is 'area'");
  expectIn(broken("spot.gltf",
                  [](json &d) {
                    d["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"]["outerConeAngle"] =
                        0.1;
                  }),
           "spot cone angles");
  expectIn(broken("camera.gltf", [](json &d) { d["cameras"][0]["perspective"]["yfov"] = 0; }),
           "camera 0 ('view') yfov");
  // A texture whose image is not a picture.
  expectIn(broken("image.gltf",
                  [](json &d) {
                    d["images"][0].erase("bufferView");
                    d["images"][0].erase("mimeType");
                    d["images"][0]["uri"] = "data:image/png;base64,AAAAAAAAAAAA";
                  }),
           "image 0");
}

}  // namespace
}  // namespace nuld
