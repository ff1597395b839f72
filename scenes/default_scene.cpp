#include "scenes/default_scene.h"

#include <cmath>
#include <numbers>

#include "materials/disney.h"
#include "materials/lambertian.h"

namespace nuld {

Image proceduralSky(int width, int height, double sunRadiance) {
  Image sky{width, height, 3, std::vector<float>(std::size_t(width) * height * 3)};
  // The sun: 35 degrees above the horizon, towards -X and +Z (behind the
  // viewer's left shoulder), about 3 degrees wide.
  const double sunElevation = 35 * std::numbers::pi / 180, sunAzimuth = 0.62;
  const Vec3 sun{std::cos(sunElevation) * std::sin(2 * std::numbers::pi * sunAzimuth),
                 std::sin(sunElevation),
                 -std::cos(sunElevation) * std::cos(2 * std::numbers::pi * sunAzimuth)};
  const double cosSun = std::cos(1.5 * std::numbers::pi / 180);
  for (int y = 0; y < height; ++y) {
    const double theta = std::numbers::pi * (y + 0.5) / height;
    for (int x = 0; x < width; ++x) {
      const double phi = 2 * std::numbers::pi * (x + 0.5) / width;
      // Same convention as EnvironmentLight: u = 0 faces -Z, u = 1/4 faces +X.
      const Vec3 d{std::sin(theta) * std::sin(phi), std::cos(theta),
                   -std::sin(theta) * std::cos(phi)};
      Rgb c;
      if (d.y > 0) {
        const double t = std::pow(1 - d.y, 3);
        c = lerp(t, Rgb{0.25, 0.45, 0.95}, Rgb{0.9, 0.95, 1.0});
      } else {
        c = Rgb{0.25, 0.22, 0.2};
      }
      if (dot(d, sun) > cosSun) c = Rgb{1.0, 0.95, 0.85} * sunRadiance;
      sky.at(x, y, 0) = float(c.r), sky.at(x, y, 1) = float(c.g), sky.at(x, y, 2) = float(c.b);
    }
  }
  return sky;
}

LoadedScene makeDefaultScene(const SceneChoices &choices) {
  const LobeChoice lobes = choices.lobes;
  std::vector<TriangleMesh> meshes;
  std::vector<std::shared_ptr<const Bsdf>> materials;
  const auto add = [&](TriangleMesh mesh, std::shared_ptr<const Bsdf> bsdf) {
    meshes.push_back(std::move(mesh));
    materials.push_back(std::move(bsdf));
  };
  DisneyParams glossy;
  glossy.baseColor = {0.8, 0.15, 0.1};
  glossy.roughness = 0.25;
  glossy.specular = 0.5;
  glossy.clearcoat = 0.5;
  add(makeSphere({-1.1, 0.5, 0}, 0.5, 48, 96, "glossy"),
      std::make_shared<DisneyBrdf>(glossy, lobes));
  DisneyParams metal;
  metal.baseColor = {0.95, 0.8, 0.5};
  metal.metallic = 1;
  metal.roughness = 0.35;
  metal.anisotropic = 0.5;
  add(makeSphere({0, 0.5, 0}, 0.5, 48, 96, "metal"), std::make_shared<DisneyBrdf>(metal, lobes));
  DisneyParams skin;
  skin.baseColor = {0.9, 0.85, 0.8};
  skin.roughness = 0.6;
  skin.subsurface = 0.8;
  skin.sheen = 0.5;
  add(makeSphere({1.1, 0.5, 0}, 0.5, 48, 96, "subsurface"),
      std::make_shared<DisneyBrdf>(skin, lobes));
  add(makeFloor(20, 0, "floor"), std::make_shared<Lambertian>(Rgb::grey(0.5)));

  LoadedScene out{"default",
                  Scene{EmbreeScene(std::move(meshes)), std::move(materials), std::nullopt, {}}};
  out.scene.lobeChoice = lobes;
  out.scene.environment.emplace(proceduralSky(512, 256), 1.0, 0.0, "procedural-sky", Vec3{0, 1, 0},
                                choices.importance.value_or(kDefaultImportance));
  out.scene.camera = {{0, 1.6, 4.2}, {0, 0.45, 0}, {0, 1, 0}, 36, false};
  out.settings.width = 192;
  out.settings.height = 128;
  out.settings.spp = 16;
  out.settings.integrator = IntegratorKind::Path;
  out.settings.maxDepth = 5;
  return out;
}

LoadedScene makeStressScene(const SceneChoices &choices) {
  const LobeChoice lobes = choices.lobes;
  LoadedScene out = makeDefaultScene(choices);
  out.name = "stress";
  std::vector<TriangleMesh> meshes;
  std::vector<std::shared_ptr<const Bsdf>> materials;
  const auto add = [&](TriangleMesh mesh, DisneyParams p) {
    meshes.push_back(std::move(mesh));
    materials.push_back(std::make_shared<DisneyBrdf>(p, lobes));
  };
  DisneyParams mirror;  // roughness 0: the GGX lobe at its smallest width
  mirror.baseColor = {0.95, 0.95, 0.95};
  mirror.metallic = 1;
  mirror.roughness = 0;
  add(makeSphere({-1.1, 0.5, 0}, 0.5, 48, 96, "mirror"), mirror);
  DisneyParams glass;  // roughness 0, dielectric, with clearcoat: two sharp lobes
  glass.baseColor = {0.1, 0.3, 0.8};
  glass.roughness = 0;
  glass.clearcoat = 1;
  glass.clearcoatGloss = 1;
  glass.anisotropic = 0.9;
  add(makeSphere({0, 0.5, 0}, 0.5, 48, 96, "smooth"), glass);
  DisneyParams rough;  // roughness 1, subsurface and sheen
  rough.baseColor = {0.9, 0.85, 0.8};
  rough.roughness = 1;
  rough.subsurface = 1;
  rough.sheen = 1;
  add(makeSphere({1.1, 0.5, 0}, 0.5, 48, 96, "rough"), rough);
  DisneyParams floor;  // a glossy floor seen at grazing angles
  floor.baseColor = {0.5, 0.5, 0.5};
  floor.roughness = 0.05;
  floor.specular = 1;
  add(makeFloor(20, 0, "floor"), floor);
  out.scene = Scene{EmbreeScene(std::move(meshes)), std::move(materials), std::nullopt, {}};
  out.scene.lobeChoice = lobes;
  // Scaled so the sun lights the scene about as the default one does; the
  // map keeps its 1e6 dynamic range.
  out.scene.environment.emplace(proceduralSky(512, 256, 1e6), 1e-3, 0.0, "procedural-sun-1e6",
                                Vec3{0, 1, 0}, choices.importance.value_or(kDefaultImportance));
  // The eye 2 cm above the floor: most floor points are seen within a few
  // degrees of grazing.
  out.scene.camera = {{0, 0.02, 4.2}, {0, 0.3, 0}, {0, 1, 0}, 36, false};
  return out;
}

}  // namespace nuld
