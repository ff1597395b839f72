// The contract every sampler backend keeps, checked over every kind of
// backend spec (sampler_backend.h): points in [0,1)^2, a pure function of
// (seed, pixel, pair), a wrong spp refused by a BackendRefusal and nothing
// else, and renders identical for any thread count.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "backends/backend_registry.h"
#include "materials/disney.h"
#include "renderer/environment_light.h"
#include "renderer/lobe_tables.h"
#include "renderer/render.h"
#include "sampler/io/pointset_io.h"
#include "sampler/neural/neural_generator.h"
#include "sampler/sequences/rng.h"
#include "tests/common/temp_dir.h"
#include "tests/renderer/test_scenes.h"

namespace nuld {
namespace {

constexpr std::size_t kSpp = 16;

// One spec of each kind: the classic backends, a point-set file (plain and
// shifted) and a neural model; the files live in a directory of the suite.
class BackendContract : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dir_ = std::make_unique<test::TempDir>();
    PointSet set;
    set.n = kSpp;
    Rng rng(3);
    for (std::size_t i = 0; i < 4 * kSpp; ++i) set.points.push_back({rng.uniform(), rng.uniform()});
    set.metadata["target"] = "uniform";
    writePointSet((*dir_ / "uniform.txt").string(), set);
    NeuralSettings ns;
    ns.n = kSpp;
    ns.hidden = 8;
    ns.family = "uniform";
    NeuralGenerator(ns).save((*dir_ / "uniform.nuldnet").string());
  }
  // The spec with its files' placeholder DIR filled in.
  std::string spec() const {
    std::string s = GetParam();
    if (const auto at = s.find("DIR"); at != std::string::npos)
      s.replace(at, 3, dir_->path().string());
    return s;
  }
  std::unique_ptr<test::TempDir> dir_;
};

// A sphere of each material kind under a map with a hot pixel: light pairs,
// lobe contexts (Disney) and classic BSDF sampling (Lambertian) all occur.
Scene contractScene() {
  DisneyParams p;
  p.roughness = 0.3;
  p.metallic = 0.6;
  Image sky = test::constantMap(0.5f, 32, 16);
  for (int c = 0; c < 3; ++c) sky.at(7, 4, c) = 40.0f;
  return test::sceneWith(
      {makeSphere({-1.1, 0, 0}, 1.0, 12, 24, "a"), makeSphere({1.1, 0, 0}, 1.0, 12, 24, "b")},
      {std::make_shared<DisneyBrdf>(p), std::make_shared<Lambertian>(Rgb::grey(0.6))}, sky,
      {{0, 0, 6}, {0, 0, 0}, {0, 1, 0}, 40});
}

TEST_P(BackendContract, PointsAreInTheUnitSquareAndAPureFunctionOfTheirArguments) {
  const Scene scene = contractScene();
  RenderSettings rs;
  rs.lobeTables.routing = LobeRouting::Table;  // every bin a context
  const LobeTables lobes(scene.materials, lobeTablesFor(rs));
  // An image large enough for the pixels asked below (zsobol orders by it).
  SamplingTargets targets{scene.environment->target(), lobes.targets(), 2048, 1024};
  auto a = makeBackend(spec(), 7), b = makeBackend(spec(), 7);
  a->prepare(kSpp, targets);
  b->prepare(kSpp, targets);
  std::vector<Point2> x(kSpp), y(kSpp), again(kSpp);
  for (std::uint64_t pixel : {0ull, 5ull, 1234567ull})
    for (std::uint32_t pair : {SampleLayout::camera, SampleLayout::light(0), SampleLayout::bsdf(0),
                               SampleLayout::light(2), SampleLayout::bsdf(3)}) {
      a->primary(pixel, pair, x);
      b->primary(pixel, pair, y);
      a->primary(pixel, pair, again);
      EXPECT_EQ(x, y) << spec() << " pixel " << pixel << " pair " << pair;
      EXPECT_EQ(x, again) << spec();
      for (const Point2 &p : x)
        ASSERT_TRUE(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1)
            << spec() << ": (" << p.x << ", " << p.y << ")";
      for (const Target *t : {targets.light, targets.lobes.front()}) {
        const bool servedA = a->distributed(*t, pixel, pair, x);
        const bool servedB = b->distributed(*t, pixel, pair, y);
        ASSERT_EQ(servedA, servedB) << spec();
        if (!servedA) continue;
        EXPECT_EQ(x, y) << spec();
        for (const Point2 &p : x) ASSERT_TRUE(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1);
      }
    }
  // The 1D domains: numbers in [0, 1), the same for the same arguments, and
  // another set for another domain.
  std::vector<double> u(kSpp), v(kSpp), w(kSpp);
  for (std::uint64_t pixel : {0ull, 5ull, 1234567ull})
    for (std::uint32_t domain : {SampleLayout::lightChoice(0), SampleLayout::lobeChoice(0),
                                 SampleLayout::roulette(0), SampleLayout::roulette(3)}) {
      a->primary1D(pixel, domain, u);
      b->primary1D(pixel, domain, v);
      a->primary1D(pixel, domain + SampleLayout::kPerBounce, w);
      EXPECT_EQ(u, v) << spec() << " pixel " << pixel << " domain " << domain;
      EXPECT_NE(u, w) << spec() << " pixel " << pixel << " domain " << domain;
      for (const double x1 : u) ASSERT_TRUE(x1 >= 0 && x1 < 1) << spec() << ": " << x1;
    }
}

TEST_P(BackendContract, AnSppItCannotServeIsRefusedAsARefusal) {
  const Scene scene = contractScene();
  const SamplingTargets targets{scene.environment->target(), {}, 64, 32};
  const auto backend = makeBackend(spec(), 1);
  // Classic backends serve any spp; those with sets of one size refuse the
  // others, and only with a BackendRefusal (a study's skipped row).
  for (const std::size_t spp : {std::size_t(1), std::size_t(3), 2 * kSpp}) {
    try {
      backend->prepare(spp, targets);
    } catch (const BackendRefusal &e) {
      EXPECT_NE(std::string(e.what()).find(std::to_string(spp)), std::string::npos) << e.what();
    } catch (const std::exception &e) {
      ADD_FAILURE() << spec() << " at spp " << spp
                    << " threw something other than a refusal: " << e.what();
    }
  }
  const bool fixedSize = spec().find(':') != std::string::npos;
  if (fixedSize) {
    EXPECT_THROW(backend->prepare(3, targets), BackendRefusal) << spec();
  }
  EXPECT_NO_THROW(backend->prepare(kSpp, targets)) << spec();
}

TEST_P(BackendContract, RendersIdenticallyForAnyThreadCount) {
  const Scene scene = contractScene();
  const RenderSettings s{24, 12, kSpp, IntegratorKind::Path, 3};
  Image one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    const auto b = makeBackend(spec(), 9);
    one = render(scene, s, *b);
  }
  const auto b = makeBackend(spec(), 9);
  const Image many = render(scene, s, *b);
  EXPECT_EQ(one.pixels, many.pixels) << spec();
  for (const float v : many.pixels) ASSERT_TRUE(std::isfinite(v)) << spec();
}

INSTANTIATE_TEST_SUITE_P(EverySpec, BackendContract,
                         ::testing::Values("independent", "sobol", "halton", "stratified", "pmj02",
                                           "zsobol", "lattice", "lattice-baker", "sobol-tabulated",
                                           "optimized:DIR/uniform.txt", "shifted:DIR/uniform.txt",
                                           "neural:DIR/uniform.nuldnet"),
                         [](const auto &info) {
                           std::string name = info.param.substr(0, info.param.find(':'));
                           for (char &c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace nuld
