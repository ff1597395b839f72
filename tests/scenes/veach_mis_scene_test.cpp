// The built-in veach-mis scene (scenes/veach_mis_scene.h).
#include <gtest/gtest.h>

#include <cmath>

#include "backends/backend_registry.h"
#include "backends/ready_backend.h"
#include "materials/disney_target.h"
#include "renderer/render.h"
#include "scenes/scene_file.h"
#include "tests/scenes/builtin_scene_checks.h"

namespace nuld {
namespace {

// Veach's MIS scene: four spheres of equal power (radiance times radius
// squared), a fifth lighting the room, Disney metal plates; every classic
// word renders finite, non-zero images under every integrator, and a camera
// ray at the smallest sphere sees its radiance.
TEST(VeachMisScene, BuildsItsLightsAndRendersFiniteValuesWithEveryClassicWord) {
  const LoadedScene s = loadScene("veach-mis", "/nonexistent");
  EXPECT_TRUE(isBuiltInScene("veach-mis"));
  EXPECT_FALSE(s.scene.environment);
  ASSERT_EQ(s.scene.lights.shapes.size(), 5u);
  ASSERT_TRUE(s.scene.lights.choice);
  for (std::size_t i = 1; i < 4; ++i)
    EXPECT_NEAR(s.scene.lights.shapes[i].power() / s.scene.lights.shapes[0].power(), 1, 3e-3) << i;
  RenderSettings small = s.settings;
  small.width = 24, small.height = 16;
  small.maxDepth = 3;
  test::expectFiniteRendersWithEveryClassicWord(s, small);
  Scene scene = loadScene("veach-mis", "").scene;
  scene.camera = {{-3.75, 0, 2}, {-3.75, 0, 0}, {0, 1, 0}, 0.1, false};
  RenderSettings one = s.settings;
  one.width = one.height = 1;
  one.spp = 1;
  auto backend = makeBackend("sobol", 1);
  EXPECT_FLOAT_EQ(render(scene, one, *backend).at(0, 0, 0), 901.803f);
}

// The learned words serve nothing here and say so, rather than render
// sobol's image under their name: no map for the map's sets, and the
// plates' lobe routes keep each plate's own sampler, so no BSDF sample goes
// through a lobe table for lobe banks or the shipped model to serve.
TEST(VeachMisScene, LearnedWordsThatServeNothingAreRefusedWithTheReason) {
  registerMaterialTargets();  // the shipped model's family, as the CLI registers it
  const LoadedScene s = loadScene("veach-mis", "");
  RenderSettings small = s.settings;
  small.width = 48, small.height = 32;
  const auto refusal = [&](const std::string &word) -> std::string {
    try {
      auto ready = makeReadyBackend(parseBackendWord(word), s.scene, small, s.name, {}, 1);
      render(s.scene, small, *ready.backend);
    } catch (const std::invalid_argument &e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(refusal("optimized").find("no (non-black) environment map"), std::string::npos);
  EXPECT_NE(refusal("optimized-bsdf").find("no BSDF sample of the scene goes through a lobe table"),
            std::string::npos);
  const std::string model = std::string(NULD_SOURCE_DIR) + "/models/disney.nuldnet";
  EXPECT_NE(
      refusal("neural:" + model).find("no BSDF sample of the scene goes through a lobe table"),
      std::string::npos);
}

}  // namespace
}  // namespace nuld
