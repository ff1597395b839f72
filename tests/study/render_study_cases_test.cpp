// The render study's cases beyond the shared tiny study
// (render_study_test.cpp): nested banks reused by another study, the map
// sets' preset, bad input, a scene without a map, the stress scene, slugs.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "backends/optimized_sets.h"
#include "backends/reference_render.h"
#include "materials/disney_target.h"
#include "sampler/io/image_io.h"
#include "sampler/io/pointset_io.h"
#include "sampler/targets/target_spec.h"
#include "scenes/scene_file.h"
#include "tests/common/temp_dir.h"
#include "tests/study/tiny_study.h"
#include "tools/study/baselines.h"
#include "tools/study/csv_table.h"
#include "tools/study/equal_time.h"
#include "tools/study/render_study.h"
#include "tools/study/report_script.h"

namespace nuld::study {
namespace {

namespace fs = std::filesystem;
using nuld::test::TempDir;
using test::asMap;
using test::readTable;
using test::tinyStudy;

// --opt-nested: one bank per target at the largest spp serves every spp;
// a second study in another directory, at an spp up to the bank's size and
// with the same cache, makes no set (its setup is the lobe tables' alone,
// which the sets' row samples where no set serves: the setup of
// sobol-tabulated, which samples the same tables, to the digit), and
// renders the same pixels as the first where the spp is the same. (The
// setups are compared within a study, where both rows count the one build
// of the tables: across the two studies, the exact sets of this tiny scene
// take milliseconds, less than the tables' build varies.)
TEST(RenderStudy, NestedBanksServeEverySppAndAreReusedByAnotherStudy) {
  TempDir tmp;
  RenderStudySettings first = tinyStudy(tmp / "first");
  first.backends = {"sobol", "sobol-tabulated", "optimized"};
  first.spp = {4, 16};
  first.repeats = 2;
  first.sets.nested = true;
  first.sets.cacheDir = tmp / "cache";
  runRenderStudy(first);
  int entries = 0;
  for (const auto &e : fs::directory_iterator(tmp / "cache" / "sets"))
    entries += e.path().extension() == ".ptsb";
  EXPECT_EQ(entries, 1) << "one nested bank of 16 serves 4 and 16";
  const CsvTable a = readTable(tmp / "first");
  // The tables' build, per spp, and the rows that made the nested bank.
  std::map<std::string, double> tablesSetup;
  for (const auto &row : a.rows()) {
    auto r = asMap(a.columns(), row);
    if (r["backend"] == "sobol-tabulated") tablesSetup[r["spp"]] = std::stod(r["setup_seconds"]);
  }
  ASSERT_EQ(tablesSetup.size(), 2u);
  for (const auto &row : a.rows()) {
    auto r = asMap(a.columns(), row);
    if (r["backend"] == "optimized") {
      EXPECT_GT(std::stod(r["setup_seconds"]), 0);
      EXPECT_GT(std::stod(r["setup_seconds"]), tablesSetup[r["spp"]]) << r["spp"];
    }
  }

  RenderStudySettings second = first;
  second.out = tmp / "second";
  second.spp = {4, 8};
  runRenderStudy(second);
  const CsvTable b = readTable(tmp / "second");
  ASSERT_EQ(b.rows().size(), 6u);
  std::set<std::string> tableSetups;
  for (const auto &row : b.rows()) {
    auto r = asMap(b.columns(), row);
    if (r["backend"] == "sobol") {
      EXPECT_EQ(std::stod(r["setup_seconds"]), 0) << r["spp"];
    } else {
      // optimized's setup is sobol-tabulated's: the tables, no set made.
      EXPECT_GT(std::stod(r["setup_seconds"]), 0) << r["spp"];
      tableSetups.insert(r["setup_seconds"]);
    }
    if (r["spp"] != "4") continue;
    for (const auto &rowA : a.rows()) {
      if (rowA[1] == r["backend"] && rowA[2] == "4") {
        EXPECT_EQ(asMap(a.columns(), rowA)["mse"], r["mse"]) << r["backend"];
      }
    }
  }
  EXPECT_EQ(tableSetups.size(), 1u) << "one build of the tables, counted by each cell";
  entries = 0;
  for (const auto &e : fs::directory_iterator(tmp / "cache" / "sets"))
    entries += e.path().extension() == ".ptsb";
  EXPECT_EQ(entries, 1) << "the second study made no set";
}

// The map's sets take the exact objective with the bank term by default (the
// sphere-exact preset) and the paper's soft boxes on --opt-objective soft:
// two entries of the set cache, each recording the settings it was made with.

TEST(RenderStudy, MapSetsTakeTheExactPresetUnlessSoftIsAsked) {
  TempDir tmp;
  std::map<std::string, std::string> settingsByObjective;
  for (const Objective objective : {Objective::ExactL2asd, Objective::SoftBoxes}) {
    RenderStudySettings s = tinyStudy(tmp / toString(objective));
    s.backends = {"optimized"};
    s.spp = {4};
    s.repeats = 1;
    s.sets.envObjective = objective;
    s.sets.cacheDir = tmp / "cache";
    runRenderStudy(s);
  }
  for (const auto &e : fs::directory_iterator(tmp / "cache" / "sets")) {
    if (e.path().extension() != ".ptsb") continue;
    const PointSet sets = readPointSet(e.path().string());
    const std::string settings = sets.metadata.at("settings");
    settingsByObjective[settings.find("objective=l2asd") != std::string::npos ? "l2asd" : "soft"] =
        settings;
  }
  ASSERT_EQ(settingsByObjective.size(), 2u);
  EXPECT_NE(settingsByObjective["l2asd"].find("preset=sphere-exact"), std::string::npos);
  EXPECT_NE(settingsByObjective["l2asd"].find("union=3/"), std::string::npos);
  EXPECT_NE(settingsByObjective["soft"].find("preset=sphere "), std::string::npos);
  EXPECT_EQ(settingsByObjective["soft"].find("union="), std::string::npos);
}

TEST(RenderStudy, BadInputGetsAClearError) {
  TempDir tmp;
  RenderStudySettings s = tinyStudy(tmp.path());
  s.backends = {"sobol", "owen-sobol"};
  try {
    runRenderStudy(s);
    FAIL();
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("owen-sobol"), std::string::npos) << e.what();
  }
  s = tinyStudy(tmp.path());
  s.spp = {4, 0};
  EXPECT_THROW(runRenderStudy(s), std::invalid_argument);
  s = tinyStudy(tmp.path());
  s.render.maxDepth = -2;
  try {
    runRenderStudy(s);
    FAIL() << "a negative depth was accepted";
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("--max-depth"), std::string::npos) << e.what();
  }
  s = tinyStudy(tmp.path());
  s.scenes = {(tmp / "missing.json").string()};
  try {
    runRenderStudy(s);
    FAIL();
  } catch (const std::exception &e) {
    EXPECT_NE(std::string(e.what()).find("missing.json"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(tmp / "render.csv")) << "nothing rendered, nothing written";
}

TEST(RenderStudy, SceneWithoutEnvironmentMapSkipsOptimizedWithTheReason) {
  // Skipping is decided before any render: a scene without a map cannot use
  // sets optimized for one. The default scene has a map, so use slug() and the
  // skip list's format through a scene JSON with no environment.
  TempDir tmp;
  const std::string scene = tmp.write("plain.json", R"({
    "camera": {"eye": [0, 1, 4], "look_at": [0, 0, 0], "fov": 40},
    "film": {"width": 8, "height": 8},
    "materials": {"default": {"type": "lambertian", "albedo": [0.5, 0.5, 0.5]}},
    "meshes": [{"shape": "sphere"}]
  })");
  RenderStudySettings s = tinyStudy(tmp / "out");
  s.scenes = {scene};
  s.backends = {"sobol", "optimized"};
  s.spp = {4};
  s.reference.spp = 8, s.reference.passSpp = 8;
  const RenderStudyResult r = runRenderStudy(s);
  ASSERT_EQ(r.skipped.size(), 1u);
  EXPECT_NE(r.skipped[0].find("plain optimized 4: the scene has no"), std::string::npos)
      << r.skipped[0];
  EXPECT_EQ(readTable(tmp / "out").rows().size(), 1u);
}

TEST(RenderStudy, StressSceneHasNoNonFiniteValueAnywhere) {
  // Roughness 0 and 1, grazing views of a glossy floor, a sun 1e6 times the
  // sky: every backend (lobe banks and tabulated lobes too), full paths and
  // BSDF sampling alone. Non-finite sample values would be dropped and
  // counted by the renderer; neither may happen.
  for (const IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Bsdf}) {
    TempDir tmp;
    RenderStudySettings s = tinyStudy(tmp.path());
    s.scenes = {"stress"};
    s.backends.insert(s.backends.end(), {"sobol-tabulated", "optimized-bsdf", "optimized-both"});
    s.render.integrator = kind;
    s.spp = {16};
    s.repeats = 1;
    s.reference.spp = 64, s.reference.passSpp = 64;
    const RenderStudyResult result = runRenderStudy(s);
    const CsvTable t = readTable(tmp.path());
    // BSDF sampling alone draws no light sample for the map's sets to serve.
    const bool bsdfOnly = kind == IntegratorKind::Bsdf;
    ASSERT_EQ(t.rows().size(), bsdfOnly ? 7u : 8u);
    ASSERT_EQ(result.skipped.size(), bsdfOnly ? 1u : 0u);
    if (bsdfOnly)
      EXPECT_NE(result.skipped[0].find("optimized 16: the bsdf integrator samples BSDFs only"),
                std::string::npos)
          << result.skipped[0];
    for (const auto &row : t.rows()) {
      auto r = asMap(t.columns(), row);
      EXPECT_EQ(r["nonfinite_pixels"], "0") << r["backend"];
      EXPECT_EQ(r["rejected_samples"], "0") << r["backend"];
      EXPECT_TRUE(std::isfinite(std::stod(r["mse"]))) << r["backend"];
    }
    const Image ref = readImage((tmp / "stress" / "reference.exr").string());
    for (float v : ref.pixels) ASSERT_TRUE(std::isfinite(v) && v >= 0);
  }
}

TEST(RenderStudy, SlugsAreFileNameSafe) {
  EXPECT_EQ(slug("default"), "default");
  EXPECT_EQ(slug("scenes/lte-orb.json"), "lte-orb");
  EXPECT_EQ(slug("neural:/tmp/models/grace 256.nuldnet"), "neural-grace_256");
  EXPECT_EQ(slug("optimized:sets.ptsb"), "optimized-sets");
  EXPECT_EQ(slug("optimized-uniform"), "optimized-uniform");
}

}  // namespace
}  // namespace nuld::study
