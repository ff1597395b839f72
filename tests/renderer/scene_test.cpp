// sceneContentKey (renderer/scene.h): the same content gives the same key
// whatever its names, and any change a render could see gives another.
#include "renderer/scene.h"

#include <gtest/gtest.h>

#include "materials/disney.h"
#include "tests/renderer/test_scenes.h"

namespace nuld {
namespace {

using test::constantMap;
using test::sceneWith;
using test::unitSphere;

struct Variant {
  TriangleMesh mesh = unitSphere(8, 16);
  std::shared_ptr<const Bsdf> material = std::make_shared<Lambertian>(Rgb::grey(0.5));
  std::optional<Image> map = constantMap(1.0f);
  CameraSettings camera{};
  std::string mapSource = "test-map";

  std::string key() const {
    Scene s = sceneWith({mesh}, {material}, std::nullopt, camera);
    if (map) s.environment.emplace(*map, 1.0, 0.0, mapSource, Vec3{0, 1, 0});
    return sceneContentKey(s);
  }
};

TEST(SceneContentKey, TheSameContentUnderOtherNamesHasTheSameKey) {
  const Variant base;
  EXPECT_EQ(base.key(), Variant{}.key());
  EXPECT_EQ(base.key().size(), 16u);
  Variant renamed;
  renamed.mesh.name = "another";
  renamed.mesh.material = "other material name";
  renamed.mapSource = "/another/root/map.exr";
  EXPECT_EQ(renamed.key(), base.key());
}

TEST(SceneContentKey, EveryChangeARenderSeesChangesIt) {
  const std::string base = Variant{}.key();
  std::vector<Variant> changed(8);
  changed[0].mesh.positions[3].x += 1e-9;
  changed[1].mesh.triangles[0][0] = changed[1].mesh.triangles[0][1];
  changed[2].material = std::make_shared<Lambertian>(Rgb::grey(0.6));
  changed[3].material = std::make_shared<DisneyBrdf>(DisneyParams{});
  changed[4].map->pixels[5] = 2.0f;
  changed[5].map.reset();
  changed[6].camera.fovDegrees = 41;
  changed[7].camera.eye.y = 0.5;
  for (std::size_t i = 0; i < changed.size(); ++i)
    EXPECT_NE(changed[i].key(), base) << "change " << i;
  // A Disney material's lobe choice and every parameter count.
  const auto disney = [](DisneyParams p, LobeChoice c) {
    Variant v;
    v.material = std::make_shared<DisneyBrdf>(p, c);
    return v.key();
  };
  DisneyParams rough;
  rough.roughness = 0.9;
  EXPECT_NE(disney({}, LobeChoice::Albedo), disney({}, LobeChoice::Uniform));
  EXPECT_NE(disney({}, LobeChoice::Albedo), disney(rough, LobeChoice::Albedo));
  EXPECT_EQ(disney(rough, LobeChoice::Albedo), disney(rough, LobeChoice::Albedo));
}

}  // namespace
}  // namespace nuld
