// Point, spot and directional lights (renderer/punctual_light.h) through
// the path tracer, against closed forms: a Lambertian floor of albedo rho
// seen straight down reflects rho / pi times the irradiance, I cos / d^2
// from a point light (times glTF's spot falloff inside a spot's cone) and
// E cos from a directional one. Each is a delta light: the light
// integrators see it exactly (no noise beyond the pixel's footprint), the
// BSDF-only integrator not at all.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "backends/backend_registry.h"
#include "renderer/render.h"
#include "tests/renderer/test_scenes.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kAlbedo = 0.6;

// A floor at y = 0 seen straight down at `at`, through one tiny pixel.
Scene floorScene(Vec3 at) {
  return test::sceneWith({makeFloor(50, 0, "floor")},
                         {std::make_shared<Lambertian>(Rgb::grey(kAlbedo))}, std::nullopt,
                         {at + Vec3{0, 3, 0}, at, {0, 0, 1}, 0.01, false});
}

double pixel(Scene &scene, IntegratorKind kind) {
  finishLights(scene);
  RenderSettings s{1, 1, 64, kind, 5, 1000};
  auto backend = makeBackend("sobol", 3);
  RenderStats stats;
  const Image img = render(scene, s, *backend, &stats);
  EXPECT_EQ(stats.rejectedSamples, 0u);
  return img.at(0, 0, 0);
}

TEST(PunctualLight, PointLightGivesTheInverseSquareLaw) {
  const Vec3 at{0.7, 0, -0.4}, light{0, 2, 0};
  const double intensity = 5;
  const Vec3 d = light - at;
  const double exact = kAlbedo / kPi * intensity * (d.y / length(d)) / dot(d, d);
  for (const IntegratorKind kind :
       {IntegratorKind::Direct, IntegratorKind::Path, IntegratorKind::Light}) {
    Scene scene = floorScene(at);
    scene.lights.punctual.push_back(PunctualLight::point(light, Rgb::grey(intensity)));
    EXPECT_NEAR(pixel(scene, kind), exact, 1e-4 * exact) << toString(kind);
  }
  // No BSDF sample can meet a point.
  Scene scene = floorScene(at);
  scene.lights.punctual.push_back(PunctualLight::point(light, Rgb::grey(intensity)));
  EXPECT_EQ(pixel(scene, IntegratorKind::Bsdf), 0.0);
}

TEST(PunctualLight, SpotLightFollowsGltfsFalloff) {
  const Vec3 light{0, 2, 0};
  const double inner = 0.2, outer = 0.5, intensity = 7;
  // Points on the floor at angles inside the inner cone, on the ramp, and
  // outside the outer cone from the spot's axis (straight down).
  for (const double angle : {0.1, 0.3, 0.45, 0.6}) {
    const Vec3 at{2 * std::tan(angle), 0, 0};
    const Vec3 d = light - at;
    const double t = std::clamp(
        (std::cos(angle) - std::cos(outer)) / (std::cos(inner) - std::cos(outer)), 0.0, 1.0);
    const double exact = kAlbedo / kPi * intensity * t * t * (d.y / length(d)) / dot(d, d);
    Scene scene = floorScene(at);
    scene.lights.punctual.push_back(
        PunctualLight::spot(light, {0, -1, 0}, Rgb::grey(intensity), inner, outer));
    // The light sample leaves from the hit lifted off the floor by the ray
    // offset, which moves the angle to the axis a little: on the ramp's
    // steep end (d ln(t^2) / d angle near 40 at 0.45 rad) that showed as a
    // relative 7e-4.
    EXPECT_NEAR(pixel(scene, IntegratorKind::Direct), exact, 2e-3 * exact + 1e-12)
        << "angle " << angle;
  }
}

TEST(PunctualLight, DirectionalLightGivesIrradianceTimesCosine) {
  const Vec3 travel = normalize(Vec3{0.5, -1, 0.2});
  const double irradiance = 3;
  const double exact = kAlbedo / kPi * irradiance * -travel.y;
  Scene scene = floorScene({0, 0, 0});
  scene.lights.punctual.push_back(PunctualLight::directional(travel, Rgb::grey(irradiance)));
  EXPECT_NEAR(pixel(scene, IntegratorKind::Path), exact, 1e-4 * exact);
}

TEST(PunctualLight, RangeEndsTheLight) {
  Scene scene = floorScene({0, 0, 0});
  scene.lights.punctual.push_back(PunctualLight::point({0, 2, 0}, Rgb::grey(5), 1.5));
  EXPECT_EQ(pixel(scene, IntegratorKind::Direct), 0.0);
}

// Chosen by power beside an area light, each light's share is unbiased:
// the two together give the sum of each alone, within the choice's noise.
TEST(PunctualLight, ChosenBesideAnAreaLightAddsUp) {
  const auto withLights = [](bool point, bool rect) {
    Scene scene = floorScene({0, 0, 0});
    if (point) scene.lights.punctual.push_back(PunctualLight::point({1, 1, 0}, Rgb::grey(2)));
    if (rect)
      scene.lights.shapes.push_back(
          AreaLight::rectangle({-2, 1, -0.5}, {1, 0, 0}, {0, 0, 1}, Rgb::grey(1)));  // faces down
    finishLights(scene);
    RenderSettings s{1, 1, 1 << 14, IntegratorKind::Direct, 5, 1000};
    auto backend = makeBackend("independent", 11);
    return render(scene, s, *backend).at(0, 0, 0);
  };
  const double both = withLights(true, true),
               sum = withLights(true, false) + withLights(false, true);
  EXPECT_NEAR(both, sum, 0.02 * sum);
}

TEST(PunctualLight, SamplesAreDeltaAndFinite) {
  const PunctualLight point = PunctualLight::point({0, 1, 0}, Rgb::grey(1));
  const auto s = point.sample({0, 0, 0});
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->delta);
  EXPECT_EQ(s->pdf, 1.0);
  EXPECT_NEAR(s->distance, 1.0, 1e-15);
  // At the light itself there is no direction.
  EXPECT_FALSE(point.sample({0, 1, 0}));
  // A tiny distance stays finite.
  const auto near = point.sample({0, 1 - 1e-150, 0});
  if (near) EXPECT_TRUE(near->radiance.isFinite());
  const auto sun = PunctualLight::directional({0, -1, 0}, Rgb::grey(2)).sample({5, 5, 5});
  ASSERT_TRUE(sun);
  EXPECT_TRUE(std::isinf(sun->distance));
  EXPECT_NEAR(sun->wi.y, 1.0, 1e-15);
}

TEST(PunctualLight, RefusesBadValues) {
  EXPECT_THROW(PunctualLight::point({}, Rgb{-1, 0, 0}), std::invalid_argument);
  EXPECT_THROW(PunctualLight::point({}, Rgb::grey(std::nan(""))), std::invalid_argument);
  EXPECT_THROW(PunctualLight::point({}, Rgb::grey(1), 0), std::invalid_argument);
  EXPECT_THROW(PunctualLight::spot({}, {0, -1, 0}, Rgb::grey(1), 0.5, 0.4), std::invalid_argument);
  EXPECT_THROW(PunctualLight::spot({}, {0, 0, 0}, Rgb::grey(1), 0.1, 0.4), std::invalid_argument);
  EXPECT_THROW(PunctualLight::directional({0, 0, 0}, Rgb::grey(1)), std::invalid_argument);
}

}  // namespace
}  // namespace nuld
