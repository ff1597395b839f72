// The render study's references (backends/reference_render.h): a
// reference resumed from its passes equals one rendered whole, bit for bit;
// one made under other settings, or before references had two halves, is
// refused, naming its state file; and it remembers its scene's content and
// the renderer's revision.
#include "backends/reference_render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "sampler/io/image_io.h"
#include "scenes/scene_file.h"
#include "tests/common/temp_dir.h"

namespace nuld {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

std::string readText(const fs::path &path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(ReferenceRender, ResumedEqualsUninterruptedBitForBit) {
  TempDir tmp;
  const LoadedScene scene = loadScene("default", resolveAssetRoot(""));
  ReferenceSettings s;
  s.spp = 12, s.passSpp = 4, s.backend = "halton";
  s.render.width = 12, s.render.height = 8;
  s.render.integrator = IntegratorKind::Path;
  const ReferenceResult whole = renderReference(scene.scene, "default", s, tmp / "whole");
  ASSERT_TRUE(whole.complete);
  EXPECT_EQ(whole.passesRun, 4u) << "12 spp: two pairs of passes of 4";
  EXPECT_EQ(s.totalSpp(), 16u);
  EXPECT_GT(whole.noise.variance, 0);
  // The reference is the mean of its halves.
  const Image h0 = readImage((tmp / "whole" / "reference.half0.exr").string()),
              h1 = readImage((tmp / "whole" / "reference.half1.exr").string());
  for (std::size_t i = 0; i < whole.image.pixels.size(); ++i)
    ASSERT_NEAR(whole.image.pixels[i], 0.5f * (h0.pixels[i] + h1.pixels[i]),
                1e-6f * (1 + whole.image.pixels[i]));

  const ReferenceResult first = renderReference(scene.scene, "default", s, tmp / "split", {}, 1);
  EXPECT_FALSE(first.complete);
  EXPECT_EQ(first.passesRun, 1u);
  EXPECT_FALSE(fs::exists(tmp / "split" / "reference.exr"));
  // A job killed after saving a round's sums but before its state: the
  // state lags by a pass, and the resume must not add that pass twice.
  const std::string lagging = readText(tmp / "split" / "reference.state");
  renderReference(scene.scene, "default", s, tmp / "split", {}, 1);
  std::ofstream(tmp / "split" / "reference.state") << lagging;
  const ReferenceResult rest = renderReference(scene.scene, "default", s, tmp / "split");
  ASSERT_TRUE(rest.complete);
  EXPECT_EQ(rest.passesRun, 2u);
  EXPECT_EQ(rest.image.pixels, whole.image.pixels);
  EXPECT_EQ(rest.noise.variance, whole.noise.variance);
  EXPECT_EQ(readImage((tmp / "split" / "reference.half1.exr").string()).pixels, h1.pixels);
  EXPECT_EQ(readImage((tmp / "split" / "reference.exr").string()).pixels, whole.image.pixels);

  // Complete: read back, nothing rendered.
  const ReferenceResult again = renderReference(scene.scene, "default", s, tmp / "split");
  EXPECT_EQ(again.passesRun, 0u);
  EXPECT_EQ(again.image.pixels, whole.image.pixels);
  EXPECT_EQ(again.noise.variance, whole.noise.variance);
}

// A reference made before the halves (its state's description has none) is
// refused with the reason, complete or in progress, and left as it was.
TEST(ReferenceRender, OldReferenceWithoutHalvesIsRefusedNotReused) {
  TempDir tmp;
  const LoadedScene scene = loadScene("default", resolveAssetRoot(""));
  ReferenceSettings s;
  s.spp = 8, s.passSpp = 4;
  s.render.width = 8, s.render.height = 8;
  for (const bool complete : {true, false}) {
    const fs::path dir = tmp / (complete ? "complete" : "partial");
    renderReference(scene.scene, "default", s, dir, {}, complete ? 0 : 1);
    // What an older nuld left: one sum or image, a state without halves.
    std::string description = s.describe(scene.scene);
    description.erase(description.find(" halves="));
    std::ofstream(dir / "reference.state")
        << "description=" << description << "\npasses_done=" << (complete ? 2 : 1)
        << "\nseconds=1\n";
    for (const char *half : {"reference.half0.exr", "reference.half1.exr"}) fs::remove(dir / half);
    const auto before = fs::last_write_time(dir / "reference.state");
    try {
      renderReference(scene.scene, "default", s, dir);
      ADD_FAILURE() << "an old reference was reused";
    } catch (const std::runtime_error &e) {
      EXPECT_NE(std::string(e.what()).find("without two independent halves"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("reference.state"), std::string::npos) << e.what();
    }
    EXPECT_EQ(fs::last_write_time(dir / "reference.state"), before);
    EXPECT_FALSE(fs::exists(dir / "reference.half0.exr"));
  }
}

TEST(ReferenceRender, OtherSettingsAreRefusedNamingTheStateFile) {
  TempDir tmp;
  const LoadedScene scene = loadScene("default", resolveAssetRoot(""));
  ReferenceSettings s;
  s.spp = 4, s.passSpp = 4;
  s.render.width = 8, s.render.height = 8;
  renderReference(scene.scene, "default", s, tmp.path());
  s.backend = "sobol";
  try {
    renderReference(scene.scene, "default", s, tmp.path());
    FAIL() << "a reference of other settings was reused";
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("reference.state"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("backend=sobol"), std::string::npos) << e.what();
  }
}

// What a reference remembers of its scene: its content key, not its name or
// path, and the renderer's revision; and that every other setting that
// changes a pixel changes the description.
TEST(ReferenceRender, DescribesTheSceneContentAndEverySetting) {
  const LoadedScene scene = loadScene("default", resolveAssetRoot(""));
  const ReferenceSettings base;
  const std::string d = base.describe(scene.scene);
  EXPECT_NE(d.find("content=" + sceneContentKey(scene.scene)), std::string::npos) << d;
  EXPECT_NE(d.find(" renderer=" + std::to_string(kRendererRevision)), std::string::npos) << d;
  std::vector<ReferenceSettings> others(7, base);
  others[0].backend = "sobol";
  others[1].spp = 8192;
  others[2].seed = 7;
  others[3].render.width = 300;
  others[4].render.integrator = IntegratorKind::Direct;
  others[5].render.maxDepth = 3;
  others[6].passSpp = 128;
  for (const ReferenceSettings &o : others) EXPECT_NE(o.describe(scene.scene), d);
  // Lobe tables count only for a backend that samples lobes.
  ReferenceSettings tables = base;
  tables.render.lobeTables.phiCells = 32;
  EXPECT_EQ(tables.describe(scene.scene), d);
  ReferenceSettings tabulated = base, tabulatedOther = tables;
  tabulated.backend = tabulatedOther.backend = "sobol-tabulated";
  EXPECT_NE(tabulated.describe(scene.scene), tabulatedOther.describe(scene.scene));
}

}  // namespace
}  // namespace nuld
