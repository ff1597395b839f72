// The render study's references from the reference cache, its repeats
// until each ratio is decided, and its robust statistic
// (tools/study/render_study.h, adaptive_repeats.h).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "sampler/io/image_io.h"
#include "tests/common/temp_dir.h"
#include "tests/study/tiny_study.h"
#include "tools/study/render_study.h"

namespace nuld::study {
namespace {

namespace fs = std::filesystem;
using nuld::test::TempDir;
using test::asMap;
using test::readTable;
using test::tinyStudy;

RenderStudySettings smallStudy(const fs::path &out, const fs::path &references) {
  RenderStudySettings s = tinyStudy(out);
  s.backends = {"independent", "sobol"};
  s.spp = {4};
  s.repeats = 2;
  s.reference.spp = 256;
  s.reference.passSpp = 128;
  s.referenceCacheDir = references;
  return s;
}

std::map<std::string, std::string> referenceRow(const fs::path &out) {
  CsvTable refs(out / "references.csv", referenceColumns(), referenceOptionalColumns());
  refs.loadExisting();
  EXPECT_EQ(refs.rows().size(), 1u);
  return refs.rows().empty() ? std::map<std::string, std::string>{}
                             : asMap(refs.columns(), refs.rows()[0]);
}

// A second study of the same scene and settings, in another folder with
// other backends, renders no reference: it finds the first one's, says so
// and counts 0 s for it.
TEST(StudyReferences, ASecondStudyFindsTheFirstOnesReference) {
  TempDir tmp;
  const RenderStudyResult first = runRenderStudy(smallStudy(tmp / "a", tmp / "refs"));
  EXPECT_TRUE(first.referencesFound.empty());
  const auto made = referenceRow(tmp / "a");
  EXPECT_EQ(made.at("cache"), "rendered");
  EXPECT_GT(std::stod(made.at("seconds")), 0);

  RenderStudySettings other = smallStudy(tmp / "b", tmp / "refs");
  other.backends = {"halton"};
  const RenderStudyResult second = runRenderStudy(other);
  ASSERT_EQ(second.referencesFound.size(), 1u);
  const auto found = referenceRow(tmp / "b");
  EXPECT_EQ(found.at("cache"), "found");
  EXPECT_EQ(std::stod(found.at("seconds")), 0);
  EXPECT_EQ(found.at("key"), made.at("key"));
  EXPECT_EQ(found.at("made_seconds"), made.at("made_seconds"));
  EXPECT_EQ(found.at("variance"), made.at("variance"));
  // Each study's folder holds the reference and its halves.
  for (const char *name : {"reference.exr", "reference.half0.exr", "reference.half1.exr"})
    EXPECT_EQ(readImage((tmp / "b" / "default" / name).string()).pixels,
              readImage((tmp / "a" / "default" / name).string()).pixels)
        << name;

  // Another resolution is another reference.
  RenderStudySettings wider = smallStudy(tmp / "c", tmp / "refs");
  wider.render.width = 40;
  EXPECT_TRUE(runRenderStudy(wider).referencesFound.empty());
}

// A reference already in a study's folder that differs from the one asked
// for is refused: the rows beside it were scored against it.
TEST(StudyReferences, AnotherReferenceInTheFolderIsRefused) {
  TempDir tmp;
  runRenderStudy(smallStudy(tmp / "a", tmp / "refs"));
  RenderStudySettings other = smallStudy(tmp / "a", tmp / "refs");
  other.reference.seed += 1;  // not a row option: only the reference differs
  try {
    runRenderStudy(other);
    FAIL() << "a study mixed two references";
  } catch (const std::exception &e) {
    EXPECT_NE(std::string(e.what()).find("reference.exr: made with"), std::string::npos)
        << e.what();
  }
}

// With a target, every row ends on precision or on its budget of repeats,
// its records are all kept, and a row's MSE is the one a fixed study with
// as many repeats makes, bit for bit (repeat r keeps seed + r).
TEST(StudyRepeats, RowsStopOnPrecisionOrBudgetAndMatchFixedRepeats) {
  TempDir tmp;
  RenderStudySettings s = smallStudy(tmp / "adaptive", tmp / "refs");
  s.budget.targetStderr = 0.05;
  s.budget.maxRepeats = 12;
  runRenderStudy(s);
  const CsvTable t = readTable(tmp / "adaptive");
  CsvTable records(tmp / "adaptive" / "default" / "repeats.csv",
                   {"backend", "spp", "repeat", "seed", "mse", "relmse", "screen_mse",
                    "mse_winsorized", "top_share", "seconds", "made_seconds", "setup_seconds",
                    "rays_per_second", "nonfinite_pixels", "rejected_samples", "flip"});
  records.loadExisting();
  std::size_t total = 0;
  std::map<std::string, std::string> independent;
  for (const auto &row : t.rows()) {
    auto r = asMap(t.columns(), row);
    const std::size_t n = std::stoul(r["repeats"]);
    total += n;
    EXPECT_GE(n, s.repeats);
    EXPECT_LE(n, s.budget.maxRepeats);
    const double worst = std::stod(r["worst_relative_stderr"]);
    if (r["stopped_on"] == "precision") {
      EXPECT_LE(worst, 0.05) << r["backend"];
    } else {
      EXPECT_EQ(r["stopped_on"], "budget") << r["backend"];
      EXPECT_GT(worst, 0.05) << r["backend"];
    }
    EXPECT_LE(std::stod(r["mse_winsorized"]), std::stod(r["mse"]));
    EXPECT_GE(std::stod(r["top_share"]), 0);
    if (r["backend"] == "independent") independent = r;
  }
  EXPECT_EQ(records.rows().size(), total);
  ASSERT_FALSE(independent.empty());
  EXPECT_GT(std::stoul(independent["repeats"]), s.repeats) << "2 repeats decide nothing";

  RenderStudySettings fixed = smallStudy(tmp / "fixed", tmp / "refs");
  fixed.backends = {"independent"};
  fixed.repeats = std::stoul(independent["repeats"]);
  runRenderStudy(fixed);
  const CsvTable f = readTable(tmp / "fixed");
  const auto r = asMap(f.columns(), f.rows().at(0));
  EXPECT_EQ(r.at("mse"), independent["mse"]);
  EXPECT_EQ(r.at("mse_stderr"), independent["mse_stderr"]);
  EXPECT_EQ(r.at("stopped_on"), "fixed");
}

// A rerun with a tighter target adds repeats to the rows of the first.
TEST(StudyRepeats, ATighterTargetOnARerunAddsRepeats) {
  TempDir tmp;
  RenderStudySettings s = smallStudy(tmp / "out", tmp / "refs");
  s.budget.targetStderr = 0.5;
  s.budget.maxRepeats = 24;
  runRenderStudy(s);
  std::map<std::string, std::size_t> before;
  const CsvTable first = readTable(tmp / "out");
  for (const auto &row : first.rows()) {
    auto r = asMap(first.columns(), row);
    before[r["backend"]] = std::stoul(r["repeats"]);
  }
  s.budget.targetStderr = 0.02;
  runRenderStudy(s);
  const CsvTable t = readTable(tmp / "out");
  bool grew = false;
  for (const auto &row : t.rows()) {
    auto r = asMap(t.columns(), row);
    EXPECT_GE(std::stoul(r["repeats"]), before[r["backend"]]);
    grew = grew || std::stoul(r["repeats"]) > before[r["backend"]];
  }
  EXPECT_TRUE(grew);

  // A rerun without a target keeps the rows and how they stopped.
  s.budget.targetStderr = 0;
  runRenderStudy(s);
  const CsvTable again = readTable(tmp / "out");
  ASSERT_EQ(again.rows().size(), t.rows().size());
  for (std::size_t i = 0; i < t.rows().size(); ++i) {
    EXPECT_EQ(again.rows()[i][t.column("repeats")], t.rows()[i][t.column("repeats")]);
    EXPECT_EQ(again.rows()[i][t.column("stopped_on")], t.rows()[i][t.column("stopped_on")]);
    EXPECT_NE(again.rows()[i][t.column("stopped_on")], "fixed");
  }
}

}  // namespace
}  // namespace nuld::study
