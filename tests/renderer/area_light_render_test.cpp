// Area lights through the path tracer (renderer/path_integrator.h): the
// radiance a Lambertian floor reflects under a sphere light, a rectangle
// light and an emitting mesh against closed forms, by each integrator kind
// (light sampling alone, BSDF sampling alone, both by MIS); a light and the
// environment chosen by power; camera rays that see the lights; and the
// stiff cases (a tiny bright sphere, grazing views) free of NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "backends/backend_registry.h"
#include "renderer/path_integrator.h"
#include "renderer/render.h"
#include "tests/renderer/test_scenes.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;

// A 1x1 image of the floor point below the camera (a very narrow field of
// view), averaged over `repeats` renders of independent seeds: the mean and
// its standard error.
struct Measured {
  double mean, stderr_;
};
Measured floorRadiance(const Scene &scene, IntegratorKind kind, std::size_t spp = 256,
                       int repeats = 24) {
  double sum = 0, sum2 = 0;
  for (int r = 0; r < repeats; ++r) {
    RenderSettings s{1, 1, spp, kind, 3};
    auto backend = makeBackend("independent", 100 + r);
    RenderStats stats;
    const Image img = render(scene, s, *backend, &stats);
    EXPECT_EQ(stats.rejectedSamples, 0u);
    const double v = img.at(0, 0, 0);
    EXPECT_TRUE(std::isfinite(v));
    sum += v, sum2 += v * v;
  }
  const double mean = sum / repeats;
  return {mean, std::sqrt(std::max(0.0, sum2 / repeats - mean * mean) / (repeats - 1))};
}

const CameraSettings kDown{{0, 4, 0}, {0, 0, 0}, {0, 0, 1}, 0.01, false};

Scene floorScene() {
  return test::sceneWith({makeFloor(50, 0, "floor")},
                         {std::make_shared<Lambertian>(Rgb::grey(0.5))}, std::nullopt, kDown);
}

void expectEveryKind(const Scene &scene, double exact, const char *what) {
  for (IntegratorKind kind : {IntegratorKind::Direct, IntegratorKind::Light, IntegratorKind::Bsdf,
                              IntegratorKind::Path}) {
    const Measured m = floorRadiance(scene, kind);
    EXPECT_NEAR(m.mean, exact, 3 * m.stderr_ + 1e-9)
        << what << ", " << toString(kind) << ": " << m.mean << " +- " << m.stderr_ << " against "
        << exact;
  }
}

// A sphere of radius r at height h over a floor of albedo rho reflects
// rho L sin^2 theta = rho L r^2 / h^2 at the point below it (the floor
// point sees the sphere's whole cap). The eye sits between the floor and
// the sphere, looking down.
TEST(AreaLightRender, FloorUnderASphereMatchesTheClosedForm) {
  Scene scene = floorScene();
  const double r = 0.5, h = 2, L = 3;
  scene.lights.shapes.push_back(AreaLight::sphere({0, h, 0}, r, Rgb::grey(L)));
  scene.camera.eye = {0, 1, 0};
  finishLights(scene);
  expectEveryKind(scene, 0.5 * L * r * r / (h * h), "sphere");
}

// Lambert's polygon formula for the rectangle's irradiance at the origin
// (normal +y).
double rectangleIrradiance(const std::vector<Vec3> &v, double L) {
  double sum = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec3 a = normalize(v[i]), b = normalize(v[(i + 1) % v.size()]);
    sum += std::acos(std::clamp(dot(a, b), -1.0, 1.0)) * normalize(cross(a, b)).y;
  }
  return 0.5 * L * std::abs(sum);
}

TEST(AreaLightRender, FloorUnderARectangleAndAnEmittingMeshMatchTheClosedForm) {
  const std::vector<Vec3> v = {{0.3, 2, -0.5}, {1.3, 2, -0.5}, {1.3, 2, 0.5}, {0.3, 2, 0.5}};
  const double L = 4, rho = 0.5;
  const double exact = rho / kPi * rectangleIrradiance(v, L);
  {
    Scene scene = floorScene();
    // Facing down: cross(edge0, edge1) = cross(+x, +z) = -y.
    scene.lights.shapes.push_back(
        AreaLight::rectangle(v[0], v[1] - v[0], v[3] - v[0], Rgb::grey(L)));
    finishLights(scene);
    expectEveryKind(scene, exact, "rectangle");
  }
  {
    // The same rectangle as two emitting triangles of a mesh (black, so it
    // reflects nothing), facing down by its winding.
    TriangleMesh panel{"panel", "", {v[0], v[1], v[2], v[3]}, {}, {{0, 1, 2}, {0, 2, 3}}};
    Scene scene = test::sceneWith(
        {makeFloor(50, 0, "floor"), panel},
        {std::make_shared<Lambertian>(Rgb::grey(rho)), std::make_shared<Lambertian>(Rgb::grey(0))},
        std::nullopt, kDown);
    addEmittingMesh(scene, 1, Rgb::grey(L), false);
    finishLights(scene);
    ASSERT_EQ(scene.lights.triangles.size(), 2u);
    expectEveryKind(scene, exact, "emitting mesh");
  }
}

// With a constant environment of radiance E beside the sphere light, the
// floor reflects rho (E (1 - sin^2 theta) + L sin^2 theta): the light that
// the sphere blocks is replaced by its own. Choosing between the two by
// power keeps the estimate unbiased.
TEST(AreaLightRender, ALightAndTheEnvironmentChosenByPower) {
  Scene scene =
      test::sceneWith({makeFloor(50, 0, "floor")}, {std::make_shared<Lambertian>(Rgb::grey(0.5))},
                      test::constantMap(0.2f), kDown);
  scene.camera.eye = {0, 1, 0};
  const double r = 0.5, h = 2, L = 3, E = 0.2, sin2 = r * r / (h * h);
  scene.lights.shapes.push_back(AreaLight::sphere({0, h, 0}, r, Rgb::grey(L)));
  finishLights(scene);
  ASSERT_TRUE(scene.lights.choice);
  EXPECT_EQ(scene.lights.choice->size(), 2u);
  expectEveryKind(scene, 0.5 * (E * (1 - sin2) + L * sin2), "sphere and environment");
}

// Camera rays see the lights: the pixel looking at a rectangle light is
// its radiance, and the back of a one-sided light is black.
TEST(AreaLightRender, CameraRaysSeeTheLights) {
  Scene scene = floorScene();
  scene.lights.shapes.push_back(
      AreaLight::rectangle({-1, 2, -1}, {2, 0, 0}, {0, 0, 2}, Rgb::grey(7)));  // faces down
  finishLights(scene);
  scene.camera = {{0, 1, 0}, {0, 5, 0}, {0, 0, 1}, 10, false};
  RenderSettings s{4, 4, 4, IntegratorKind::Path, 3};
  auto backend = makeBackend("sobol", 1);
  EXPECT_FLOAT_EQ(render(scene, s, *backend).at(1, 1, 0), 7.0f);
  scene.camera = {{0, 3, 0}, {0, 0, 0}, {0, 0, 1}, 10, false};  // from above: its back
  EXPECT_FLOAT_EQ(render(scene, s, *backend).at(1, 1, 0), 0.0f);
}

// A tiny bright sphere (radius 0.05, radiance 3000) and grazing views:
// finite pixels under every backend kind and integrator.
TEST(AreaLightRender, TinyBrightLightsAndGrazingViewsStayFinite) {
  Scene scene = floorScene();
  scene.lights.shapes.push_back(AreaLight::sphere({0.3, 0.2, 0.1}, 0.05, Rgb::grey(3000)));
  scene.lights.shapes.push_back(
      AreaLight::rectangle({-2, 0.001, -2}, {4, 0, 0}, {0, 0, 4}, Rgb::grey(10)));
  finishLights(scene);
  scene.camera = {{-3, 0.05, 0}, {3, 0, 0.2}, {0, 1, 0}, 60, false};
  for (const char *word : {"independent", "sobol", "halton", "zsobol", "pmj02", "stratified"})
    for (IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Direct, IntegratorKind::Light,
                                IntegratorKind::Bsdf}) {
      RenderSettings s{24, 16, 8, kind, 4};
      auto backend = makeBackend(word, 2);
      RenderStats stats;
      const Image img = render(scene, s, *backend, &stats);
      for (float v : img.pixels) ASSERT_TRUE(std::isfinite(v)) << word << " " << toString(kind);
      EXPECT_EQ(stats.rejectedSamples, 0u) << word << " " << toString(kind);
    }
}

}  // namespace
}  // namespace nuld
