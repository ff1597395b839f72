// The path tracer end to end on scenes whose answers are known: white
// furnaces, stiff cases that must stay finite, and determinism.

#include "renderer/render.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "backends/backend_registry.h"
#include "materials/disney.h"
#include "renderer/image_metrics.h"
#include "renderer/path_integrator.h"
#include "tests/renderer/test_scenes.h"

namespace nuld {
namespace {

using test::constantMap;
using test::sceneWith;
using test::unitSphere;

const CameraSettings kLookAtSphere{{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40, false};

double meanOf(const Image &img) {
  double s = 0;
  for (float v : img.pixels) s += v;
  return s / img.pixels.size();
}

bool allFinite(const Image &img) {
  for (float v : img.pixels)
    if (!std::isfinite(v)) return false;
  return true;
}

// A convex sphere of albedo a in a uniform environment of radiance 1
// reflects exactly a everywhere: light that leaves it never returns.
TEST(Render, WhiteFurnaceLambertianSphere) {
  for (double albedo : {1.0, 0.5}) {
    const Scene scene = sceneWith({unitSphere()}, {std::make_shared<Lambertian>(Rgb::grey(albedo))},
                                  constantMap(1.0f), kLookAtSphere);
    for (IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Direct, IntegratorKind::Light,
                                IntegratorKind::Bsdf}) {
      RenderSettings s{32, 32, 64, kind, 5};
      auto backend = makeBackend("sobol", 1);
      RenderStats stats;
      const Image img = render(scene, s, *backend, &stats);
      EXPECT_EQ(stats.rejectedSamples, 0u);
      // The centre 8x8 pixels all see the sphere.
      double sum = 0;
      for (int y = 12; y < 20; ++y)
        for (int x = 12; x < 20; ++x) sum += img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2);
      EXPECT_NEAR(sum / (64 * 3), albedo, 0.01 * albedo) << toString(kind);
      // The background is the environment itself.
      EXPECT_NEAR(img.at(0, 0, 1), 1.0, 1e-6);
    }
  }
}

// The terminator policy (path_integrator.cpp, shadingAt): on a coarse
// smooth-shaded sphere every direction of the shading hemisphere must escape,
// including those below the flat triangle. With BSDF sampling alone each
// escaping sample of a Lambertian surface returns exactly the albedo, so any
// direction dropped or self-shadowed shows as a pixel below it. Dropping
// them (the policy before) read 0.79992 for 0.8 on a finer sphere; this one
// is coarse (8 x 16) to make the effect large.
TEST(Render, WhiteFurnaceSmoothShadedSphereReturnsTheAlbedo) {
  const double albedo = 0.8;
  const Scene scene = sceneWith({makeSphere({0, 0, 0}, 1.0, 8, 16, "coarse")},
                                {std::make_shared<Lambertian>(Rgb::grey(albedo))},
                                constantMap(1.0f), kLookAtSphere);
  RenderSettings s{32, 32, 64, IntegratorKind::Bsdf, 5};
  auto backend = makeBackend("sobol", 3);
  const Image img = render(scene, s, *backend);
  // Pixels within 7 of the centre see only the sphere (its image has a
  // radius of about 11 pixels).
  double lowest = 1, sum = 0;
  int count = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      if ((x - 15.5) * (x - 15.5) + (y - 15.5) * (y - 15.5) > 49) continue;
      for (int c = 0; c < 3; ++c) lowest = std::min(lowest, double(img.at(x, y, c)));
      sum += img.at(x, y, 1);
      ++count;
    }
  EXPECT_NEAR(sum / count, albedo, 1e-6);
  EXPECT_GT(lowest, albedo - 1e-6);
}

// Russian roulette changes the noise, never the expectation: a sphere on a
// floor of albedo 0.9 (interreflections down to max depth 8) renders to the
// same image mean with roulette from the third hit (the default) as with
// none, within 4 standard errors over 6 Owen-Sobol seeds each. Survivors not
// divided by their survival probability read 0.9074 against 0.9127: five
// times the bound.
TEST(Render, RussianRouletteKeepsTheExpectation) {
  const Scene scene = sceneWith(
      {makeFloor(5, -1, "floor"), makeSphere({0, 0, 0}, 1.0, 24, 48, "sphere")},
      {std::make_shared<Lambertian>(Rgb::grey(0.9)), std::make_shared<Lambertian>(Rgb::grey(0.9))},
      constantMap(1.0f), {{0, 1.5, 4}, {0, -0.5, 0}, {0, 1, 0}, 60, false});
  auto meanAndStdErr = [&](int rouletteDepth) {
    RenderSettings s{24, 24, 64, IntegratorKind::Path, 8};
    s.rouletteDepth = rouletteDepth;
    std::vector<double> means;
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      auto backend = makeBackend("sobol", seed);
      means.push_back(meanOf(render(scene, s, *backend)));
    }
    double m = 0, v = 0;
    for (double x : means) m += x / means.size();
    for (double x : means) v += (x - m) * (x - m) / (means.size() - 1);
    return std::pair{m, std::sqrt(v / means.size())};
  };
  const auto [withRoulette, seWith] = meanAndStdErr(2);
  const auto [without, seWithout] = meanAndStdErr(1000);
  EXPECT_NEAR(withRoulette, without, 4 * std::hypot(seWith, seWithout))
      << "standard errors " << seWith << ", " << seWithout;
  EXPECT_GT(seWith, 0);
}

// A white, non-metallic Disney material with no specular reflects at most
// what comes in; its furnace value is bounded by 1 (Burley's diffuse is not
// exactly energy conserving, so only the bound is asserted), whichever way
// the material picks its lobes.
TEST(Render, DisneySphereInFurnaceStaysBelowOne) {
  DisneyParams p;
  p.specular = 0;
  p.roughness = 0.5;
  for (const LobeChoice choice : {LobeChoice::Uniform, LobeChoice::Weight, LobeChoice::Albedo}) {
    const Scene scene = sceneWith({unitSphere()}, {std::make_shared<DisneyBrdf>(p, choice)},
                                  constantMap(1.0f), kLookAtSphere);
    RenderSettings s{24, 24, 64, IntegratorKind::Path, 5};
    auto backend = makeBackend("sobol", 2);
    const Image img = render(scene, s, *backend);
    EXPECT_TRUE(allFinite(img));
    double sum = 0;
    for (int y = 9; y < 15; ++y)
      for (int x = 9; x < 15; ++x) sum += img.at(x, y, 1);
    EXPECT_LT(sum / 36, 1.05) << toString(choice);
    EXPECT_GT(sum / 36, 0.5) << toString(choice);
  }
}

// Stiff cases: mirror-like and fully rough materials, every lobe, grazing
// views, a black sky and a sun 1e6 times brighter than the sky, under every
// lobe choice.
TEST(Render, StiffCasesStayFinite) {
  Image sun = constantMap(1.0f, 64, 32);
  for (int c = 0; c < 3; ++c) sun.at(40, 6, c) = 1e6f;
  std::vector<std::pair<std::string, Image>> maps = {
      {"black", constantMap(0.0f)}, {"sun", sun}, {"grey", constantMap(0.5f)}};
  std::vector<DisneyParams> materials;
  for (double roughness : {0.0, 1.0})
    for (double metallic : {0.0, 1.0}) {
      DisneyParams p;
      p.roughness = roughness;
      p.metallic = metallic;
      p.anisotropic = 0.9;
      p.subsurface = 1;
      p.clearcoat = 1;
      p.sheen = 1;
      materials.push_back(p);
    }
  // A camera that grazes the sphere's silhouette, and one inside the sphere.
  const std::vector<CameraSettings> cameras = {{{0, 1.0, 4}, {0, 1.0, 0}, {0, 1, 0}, 5, false},
                                               {{0, 0, 0.5}, {0, 0, -1}, {0, 1, 0}, 90, false}};
  for (const auto &[name, map] : maps)
    for (const DisneyParams &p : materials)
      for (const CameraSettings &cam : cameras)
        for (const LobeChoice choice :
             {LobeChoice::Uniform, LobeChoice::Weight, LobeChoice::Albedo}) {
          const Scene scene =
              sceneWith({unitSphere(8, 16)}, {std::make_shared<DisneyBrdf>(p, choice)}, map, cam);
          // The classic mapping, and tabulated lobes (small tables: the
          // stiff lobes alias in any table, which must cost only variance).
          for (const auto &[backendName, kind] : {std::pair{"independent", IntegratorKind::Path},
                                                  {"sobol-tabulated", IntegratorKind::Path},
                                                  {"sobol-tabulated", IntegratorKind::Bsdf}}) {
            RenderSettings s{12, 12, 8, kind, 8};
            s.lobeTables = {3, 2, 32, std::nullopt};
            auto backend = makeBackend(backendName, 3);
            RenderStats stats;
            const Image img = render(scene, s, *backend, &stats);
            EXPECT_TRUE(allFinite(img)) << name << " " << backendName;
            EXPECT_EQ(stats.rejectedSamples, 0u) << name << " roughness " << p.roughness;
            if (name == "black") {
              EXPECT_EQ(meanOf(img), 0.0);
            }
          }
        }
}

TEST(Render, DeterministicForAnyThreadCount) {
  const Scene scene = sceneWith({unitSphere()}, {std::make_shared<Lambertian>(Rgb::grey(0.7))},
                                constantMap(1.0f), kLookAtSphere);
  RenderSettings s{40, 24, 8, IntegratorKind::Path, 5};
  Image one, many;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    auto b = makeBackend("halton", 9);
    one = render(scene, s, *b);
  }
  auto b = makeBackend("halton", 9);
  many = render(scene, s, *b);
  EXPECT_EQ(one.pixels, many.pixels);
}

// A glossy metal sphere under a map with a hot spot: the direct-lighting test
// scene of the tests below.
Scene glossySphereUnderHotSpot() {
  Image sky = constantMap(0.3f, 32, 16);
  for (int y = 2; y < 5; ++y)
    for (int c = 0; c < 3; ++c) sky.at(9, y, c) = 60.0f;
  DisneyParams p;
  p.roughness = 0.4;
  p.metallic = 0.5;
  return sceneWith({unitSphere()}, {std::make_shared<DisneyBrdf>(p)}, sky, kLookAtSphere);
}

// The integrator advances up to 16 paths together; each must come out exactly
// as if traced alone (the oracle: the same path in a call of its own). A
// sphere on a floor, so paths bounce between them, escape, end by roulette
// or by depth; pixels where the sphere meets the floor.
TEST(Render, PathsTracedTogetherEqualPathsTracedAlone) {
  DisneyParams p;
  p.roughness = 0.3;
  p.metallic = 0.7;
  Image sky = constantMap(0.3f, 32, 16);
  for (int c = 0; c < 3; ++c) sky.at(9, 3, c) = 60.0f;
  const Scene scene =
      sceneWith({unitSphere(), makeFloor(6, -1, "floor")},
                {std::make_shared<DisneyBrdf>(p), std::make_shared<Lambertian>(Rgb::grey(0.8))},
                sky, kLookAtSphere);
  const PerspectiveCamera camera(kLookAtSphere, 32, 32);
  for (const char *name : {"sobol", "independent"}) {
    auto backend = makeBackend(name, 3);
    backend->prepare(16, {scene.environment->target()});
    const PathIntegrator integrator(scene, IntegratorKind::Path, 6);
    for (int pixel : {16 * 32 + 16, 24 * 32 + 12, 26 * 32 + 20}) {
      PixelSamples together(*backend, 16);
      together.startPixel(pixel);
      std::array<Ray, 16> rays;
      std::array<std::optional<SurfaceHit>, 16> hits;
      std::array<PixelSamples *, 16> samples;
      std::array<std::size_t, 16> indices;
      std::array<Rgb, 16> L;
      for (std::size_t k = 0; k < 16; ++k) {
        const Point2 j = together.primary(SampleLayout::camera, k);
        rays[k] = camera.generateRay({pixel % 32 + j.x, pixel / 32 + j.y});
        hits[k] = scene.geometry.intersect(rays[k]);
        samples[k] = &together;
        indices[k] = k;
      }
      PathCounters counters;
      integrator.radiance(rays, hits, samples, indices, L, counters);
      for (std::size_t k = 0; k < 16; ++k) {
        PixelSamples alone(*backend, 16);
        alone.startPixel(pixel);
        PixelSamples *one = &alone;
        Rgb single;
        integrator.radiance(std::span(&rays[k], 1), std::span(&hits[k], 1), std::span(&one, 1),
                            std::span(&indices[k], 1), std::span(&single, 1), counters);
        EXPECT_EQ(L[k].r, single.r) << name << " pixel " << pixel << " path " << k;
        EXPECT_EQ(L[k].g, single.g);
        EXPECT_EQ(L[k].b, single.b);
      }
    }
  }
}

// Direct lighting by light sampling alone and by MIS of light and BSDF
// samples are two unbiased estimators of the same image: their 4096-spp
// renders agree to within their noise (measured relMSE 5e-4 between them at
// 2048 spp), and the light-only one is the noisier at low spp (the highlight
// is what BSDF sampling is for).
TEST(Render, LightSamplingAloneAgreesWithMisDirectLighting) {
  const Scene scene = glossySphereUnderHotSpot();
  auto a = makeBackend("sobol", 1234), b = makeBackend("sobol", 99);
  const Image mis = render(scene, {16, 16, 4096, IntegratorKind::Direct, 1}, *a);
  const Image light = render(scene, {16, 16, 4096, IntegratorKind::Light, 1}, *b);
  ASSERT_TRUE(allFinite(light));
  EXPECT_NEAR(meanOf(light), meanOf(mis), 0.005 * meanOf(mis));
  EXPECT_LT(compareImages(light, mis).relmse, 2e-3);
  auto c = makeBackend("sobol", 5), d = makeBackend("sobol", 5);
  const Image misLow = render(scene, {16, 16, 8, IntegratorKind::Direct, 1}, *c);
  const Image lightLow = render(scene, {16, 16, 8, IntegratorKind::Light, 1}, *d);
  EXPECT_GT(compareImages(lightLow, mis).mse, compareImages(misLow, mis).mse);
}

// MIS compensation changes where the light samples, not what the estimator
// converges to; under a sky with a hot spot it lowers a diffuse sphere's
// noise (measured at 16 spp, 8 seeds: MSE ratio 0.145). The light
// integrator, which has no BSDF samples to cover the dim sky, samples the
// map without its compensation: the same image as the plain map's.
TEST(Render, MisCompensationKeepsTheExpectationAndLowersNoise) {
  Image sky = constantMap(0.3f, 32, 16);
  for (int y = 2; y < 5; ++y)
    for (int c = 0; c < 3; ++c) sky.at(9, y, c) = 60.0f;
  const auto diffuse = std::make_shared<Lambertian>(Rgb{0.8, 0.8, 0.8});
  const Scene plain =
      sceneWith({unitSphere()}, {diffuse}, sky, kLookAtSphere, PixelWeight::ChannelMean);
  const Scene compensated =
      sceneWith({unitSphere()}, {diffuse}, sky, kLookAtSphere, PixelWeight::ChannelMeanCompensated);
  auto a = makeBackend("sobol", 1), b = makeBackend("sobol", 2);
  const Image reference = render(plain, {16, 16, 8192, IntegratorKind::Direct, 1}, *a);
  const Image converged = render(compensated, {16, 16, 8192, IntegratorKind::Direct, 1}, *b);
  ASSERT_TRUE(allFinite(converged));
  EXPECT_NEAR(meanOf(converged), meanOf(reference), 0.003 * meanOf(reference));
  double plainMse = 0, compensatedMse = 0;
  for (std::uint64_t seed = 10; seed < 18; ++seed) {
    auto p = makeBackend("independent", seed), c = makeBackend("independent", seed);
    plainMse +=
        compareImages(render(plain, {16, 16, 16, IntegratorKind::Direct, 1}, *p), reference).mse;
    compensatedMse +=
        compareImages(render(compensated, {16, 16, 16, IntegratorKind::Direct, 1}, *c), reference)
            .mse;
  }
  std::printf("MSE at 16 spp: plain %.4g, compensated %.4g (ratio %.3f)\n", plainMse / 8,
              compensatedMse / 8, compensatedMse / plainMse);
  EXPECT_LT(compensatedMse, 0.5 * plainMse);
  auto l = makeBackend("sobol", 3), m = makeBackend("sobol", 3);
  const Image lightPlain = render(plain, {16, 16, 4, IntegratorKind::Light, 1}, *l);
  const Image lightCompensated = render(compensated, {16, 16, 4, IntegratorKind::Light, 1}, *m);
  EXPECT_EQ(lightCompensated.pixels, lightPlain.pixels);
}

// QMC backends must keep converging at high spp. Before their pairs were
// shuffled (renderer/padding.h), every pair of a pixel was a scrambled copy
// of the same net matched to the others by index, and sobol's and halton's
// MSE here stayed at 8e-3 and 4e-3 from 256 to 4096 spp. Measured after: sobol
// 2.6e-3 / 4.9e-5 at 64 / 1024 spp, halton 1.9e-3 / 1.1e-4, independent
// 9.4e-3 / 4.3e-4 (mean of 4 seeds against a 65536-spp independent reference).
// Asserted: 16x the samples divide the MSE by more than 8, and at 1024 spp
// both beat independent sampling.
TEST(Render, QmcErrorKeepsFallingAtHighSpp) {
  const Scene scene = glossySphereUnderHotSpot();
  auto refBackend = makeBackend("independent", 77);
  const Image reference = render(scene, {16, 16, 65536, IntegratorKind::Direct, 1}, *refBackend);
  const auto mse = [&](const char *name, std::size_t spp) {
    double sum = 0;
    for (int seed : {1, 2, 3, 4}) {
      auto backend = makeBackend(name, seed);
      sum += compareImages(render(scene, {16, 16, spp, IntegratorKind::Direct, 1}, *backend),
                           reference)
                 .mse;
    }
    return sum / 4;
  };
  const double independent = mse("independent", 1024);
  for (const char *name : {"sobol", "halton"}) {
    const double low = mse(name, 64), high = mse(name, 1024);
    EXPECT_LT(8 * high, low) << name;
    EXPECT_LT(high, independent) << name;
  }
}

// Against a high-spp reference, the error of every backend falls as spp grows.
TEST(Render, ErrorFallsWithSppForEveryBackend) {
  const Scene scene = glossySphereUnderHotSpot();
  auto refBackend = makeBackend("sobol", 1234);
  const Image reference = render(scene, {16, 16, 2048, IntegratorKind::Direct, 1}, *refBackend);
  for (const char *name : {"independent", "sobol", "halton"}) {
    double previous = 1e300;
    for (std::size_t spp : {4, 32, 256}) {
      auto backend = makeBackend(name, 7);
      const Image img = render(scene, {16, 16, spp, IntegratorKind::Direct, 1}, *backend);
      const double mse = compareImages(img, reference).mse;
      EXPECT_LT(mse, previous) << name << " at spp " << spp;
      previous = mse;
    }
  }
}

}  // namespace
}  // namespace nuld
