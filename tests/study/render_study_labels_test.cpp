// Labelled rows of the render study (LABEL=WORD, backends/ready_backend.h):
// the label names the row's files and the table's label column, the word
// decides how it is classed and scored; bad labels are refused.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "backends/ready_backend.h"
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

TEST(RowLabels, SplitWhereALabelCanEnd) {
  EXPECT_EQ(rowLabel("best=optimized-both"), "best");
  EXPECT_EQ(unlabelled("best=optimized-both"), "optimized-both");
  EXPECT_EQ(rowLabel("sobol"), "sobol");
  // A '=' in a plugin's arguments is the word's own.
  EXPECT_EQ(rowLabel("plugin:/x/libmine.so:seed=3"), "plugin:/x/libmine.so:seed=3");
  EXPECT_EQ(unlabelled("mine=plugin:/x/libmine.so:seed=3"), "plugin:/x/libmine.so:seed=3");
  const BackendWord w = parseBackendWord("pts=pmj02");
  EXPECT_EQ(w.word, "pts=pmj02");
  EXPECT_EQ(w.label, "pts");
  EXPECT_EQ(w.spec.kind, parseBackendWord("pmj02").spec.kind);
  EXPECT_THROW(parseBackendWord("=sobol"), std::invalid_argument);
  EXPECT_THROW(parseBackendWord("x=nonesuch"), std::invalid_argument);
}

// A labelled classic row and a labelled plugin row: files and labels named
// for the labels; the plugin row is scored against the best built-in
// classic row, which the labelled pmj02 may be.
TEST(RowLabels, NameTheRowsFilesAndKeepTheirWordsClass) {
  TempDir tmp;
  RenderStudySettings s = tinyStudy(tmp / "out");
  s.backends = {"sobol", "pts=pmj02", std::string("mine=plugin:") + NULD_EXAMPLE_PLUGIN};
  s.spp = {4};
  s.repeats = 2;
  s.reference.spp = 256;
  s.reference.passSpp = 128;
  runRenderStudy(s);
  EXPECT_TRUE(fs::exists(tmp / "out" / "default" / "pts_spp4.exr"));
  EXPECT_TRUE(fs::exists(tmp / "out" / "default" / "mine_spp4.exr"));
  const CsvTable t = readTable(tmp / "out");
  ASSERT_EQ(t.rows().size(), 3u);
  for (const auto &r : t.rows()) {
    const auto row = asMap(t.columns(), r);
    const std::string backend = row.at("backend");
    EXPECT_EQ(row.at("label"), rowLabel(backend));
    EXPECT_TRUE(row.at("best_classic") == "sobol" || row.at("best_classic") == "pts=pmj02")
        << row.at("best_classic");
    const bool plugin = backend.starts_with("mine=");
    EXPECT_EQ(std::isfinite(std::stod(row.at("mse_ratio_best_classic"))), plugin) << backend;
    if (plugin) {
      // No setup: no break-even renders.
      EXPECT_FALSE(std::isfinite(std::stod(row.at("break_even_renders"))));
    }
  }
}

TEST(RowLabels, TwoRowsOfOneNameAreRefused) {
  TempDir tmp;
  RenderStudySettings s = tinyStudy(tmp / "out");
  s.backends = {"sobol", "sobol=pmj02"};
  try {
    runRenderStudy(s);
    FAIL() << "two rows named sobol ran";
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("two rows named 'sobol'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nuld::study
