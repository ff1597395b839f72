// The neural:MODEL backend: which pairs it serves, the bank of sets, and the
// reasons it refuses a model.

#include "backends/neural_backend.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "backends/backend_registry.h"
#include "materials/disney_target.h"
#include "renderer/environment_light.h"
#include "renderer/lobe_tables.h"
#include "renderer/render.h"
#include "sampler/io/image_io.h"
#include "tests/common/temp_dir.h"
#include "tests/renderer/test_scenes.h"

namespace nuld {
namespace {

std::string saveModel(const test::TempDir &dir, const std::string &name, const std::string &family,
                      std::size_t n) {
  NeuralSettings s;
  s.n = n;
  s.hidden = 8;
  s.family = family;
  const std::string path = (dir / name).string();
  NeuralGenerator(s).save(path);
  return path;
}

std::string errorOf(const std::function<void()> &f) {
  try {
    f();
  } catch (const std::invalid_argument &e) {
    return e.what();
  }
  return "";
}

TEST(NeuralBackend, EnvironmentModelServesTheFirstLightPairFromItsBank) {
  const test::TempDir dir;
  const std::string mapPath = (dir / "map.exr").string();
  test::writeHotPixelMap(mapPath);
  const EnvironmentLight light(readImage(mapPath), 1.0, 0.0, mapPath);
  const EnvironmentLight other(test::constantMap(1.0f), 1.0, 0.0, "other.exr");
  const std::string model = saveModel(dir, "env.nuldnet", "envmap:" + mapPath, 8);

  NeuralBackend backend("neural:" + model, model, 4);
  backend.prepare(8, {light.target()});
  EXPECT_GT(backend.bankSets(), 1000u);
  std::vector<Point2> a(8), b(8);
  ASSERT_TRUE(backend.distributed(*light.target(), 5, SampleLayout::light(0), a));
  ASSERT_TRUE(backend.distributed(*light.target(), 6, SampleLayout::light(0), b));
  EXPECT_NE(a, b);  // pixels draw different offsets
  for (const Point2 &p : a) EXPECT_TRUE(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1);
  EXPECT_FALSE(backend.distributed(*light.target(), 5, SampleLayout::light(1), a));
  EXPECT_FALSE(backend.distributed(*other.target(), 5, SampleLayout::light(0), a));

  EXPECT_NE(errorOf([&] { backend.prepare(16, {light.target()}); }).find("--spp 8"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { backend.prepare(8, {}); }).find("no environment map"), std::string::npos);
  EXPECT_NE(errorOf([&] { backend.prepare(8, {other.target()}); }).find("other.exr"),
            std::string::npos);
}

TEST(NeuralBackend, UniformModelIsShiftedPerPixelAndRendersFiniteImages) {
  const test::TempDir dir;
  const std::string model = saveModel(dir, "u.nuldnet", "uniform", 4);
  auto backend = makeBackend("neural:" + model, 1);
  backend->prepare(4, {});
  std::vector<Point2> a(4), b(4);
  backend->primary(3, SampleLayout::camera, a);
  backend->primary(3, SampleLayout::bsdf(0), b);
  EXPECT_NE(a, b);
  const Scene scene =
      test::sceneWith({test::unitSphere()}, {std::make_shared<Lambertian>(Rgb::grey(0.5))},
                      test::constantMap(1.0f), {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40, false});
  RenderStats stats;
  const Image image = render(scene, {8, 8, 4, IntegratorKind::Path, 4}, *backend, &stats);
  for (float v : image.pixels) EXPECT_TRUE(std::isfinite(v));
  EXPECT_EQ(stats.rejectedSamples, 0u);
}

// A model of family:disney serves the BSDF pair of a material with the
// family's parameters: one bank per lobe table, generated at the table's
// gamma, whose points follow that table (they start as its inverse-CDF
// image, and the untrained network adds nothing). A material with other
// parameters is not served.
TEST(NeuralBackend, DisneyFamilyModelServesTheLobeTablesOfItsMaterial) {
  registerMaterialTargets();  // what nuld's main does
  const test::TempDir dir;
  const std::string model = saveModel(dir, "lobe.nuldnet", "family:disney", 4);
  NeuralBackend backend("neural:" + model, model, 2);
  ASSERT_TRUE(backend.samplesLobes());
  const auto supplement = std::make_shared<DisneyBrdf>(supplementDisneyParams());
  const LobeTables tables({supplement}, LobeTableSettings{3, 2, 256, 0.0, LobeRouting::Table});
  const auto targets = tables.targets();
  backend.prepare(4, {nullptr, targets});
  EXPECT_EQ(backend.servedTargets(), targets.size());
  EXPECT_EQ(backend.bankSets(), targets.size() * NeuralBackend::kSetsPerGamma);
  // It made the banks (setup a study reports apart from render time);
  // another backend of the same model finds them made, and makes nothing.
  EXPECT_GT(backend.report().setsMadeSeconds, 0);
  NeuralBackend again("neural:" + model, model, 3);
  again.prepare(4, {nullptr, targets});
  EXPECT_EQ(again.servedTargets(), targets.size());
  EXPECT_EQ(again.report().setsMadeSeconds, 0);
  std::vector<Point2> out(4);
  for (const Target *t : targets) {
    ASSERT_TRUE(backend.distributed(*t, 9, SampleLayout::bsdf(0), out));
    for (const Point2 &p : out) EXPECT_GT(t->pdf(p), 0) << t->spec();
    EXPECT_FALSE(backend.distributed(*t, 9, SampleLayout::bsdf(1), out));
  }
  DisneyParams other = supplementDisneyParams();
  other.roughness = 0.2;
  const LobeTables otherTables({std::make_shared<DisneyBrdf>(other)},
                               LobeTableSettings{3, 2, 256, 0.0, LobeRouting::Table});
  EXPECT_NE(errorOf([&] {
              backend.prepare(4, {nullptr, otherTables.targets()});
            }).find("makes none of the scene's"),
            std::string::npos);
}

TEST(NeuralBackend, RefusesModelsThatNeedGammaAndUnreadableFiles) {
  const test::TempDir dir;
  const std::string model = saveModel(dir, "g.nuldnet", "family:gaussian", 4);
  EXPECT_NE(errorOf([&] { makeBackend("neural:" + model, 0); }).find("gamma"), std::string::npos);
  EXPECT_THROW(makeBackend("neural:" + (dir / "absent").string(), 0), std::runtime_error);
  // `neural` alone is the shipped model; $NULD_LOBE_MODEL names another,
  // and one that cannot be read is refused naming it.
  registerMaterialTargets();
  const char *before = std::getenv("NULD_LOBE_MODEL");
  const std::string saved = before ? before : "";
  unsetenv("NULD_LOBE_MODEL");
  EXPECT_NO_THROW(makeBackend("neural", 0));
  setenv("NULD_LOBE_MODEL", (dir / "absent.nuldnet").c_str(), 1);
  try {
    makeBackend("neural", 0);
    ADD_FAILURE() << "an absent $NULD_LOBE_MODEL was accepted";
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("absent.nuldnet"), std::string::npos) << e.what();
  }
  if (before) {
    setenv("NULD_LOBE_MODEL", saved.c_str(), 1);
  } else {
    unsetenv("NULD_LOBE_MODEL");
  }

  // A model whose offsets do not span the torus makes unrandomized sets.
  NeuralSettings narrow;
  narrow.n = 4;
  narrow.hidden = 8;
  narrow.family = "uniform";
  narrow.offsetRange = 0.0625;
  const std::string narrowPath = (dir / "narrow.nuldnet").string();
  NeuralGenerator(narrow).save(narrowPath);
  const std::string why = errorOf([&] { makeBackend("neural:" + narrowPath, 0); });
  EXPECT_NE(why.find("--offset-range"), std::string::npos) << why;
  EXPECT_NE(why.find(narrowPath), std::string::npos) << why;
}

}  // namespace
}  // namespace nuld
