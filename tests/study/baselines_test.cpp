// The render study's baselines (tools/study/baselines.h): the reference's
// own noise against a known variance, on synthetic halves and on rendered
// references against the spread of many independent ones; the best classic
// row, its ratio, the noise flag and the break-even renders by hand from a
// small CSV; and which backend words count as classic.

#include "tools/study/baselines.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sampler/io/image_io.h"
#include "scenes/scene_file.h"
#include "tests/common/temp_dir.h"
#include "tools/study/csv_table.h"
#include "tools/study/render_study.h"

namespace nuld::study {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// Two halves of a reference whose per-value variance is v(i): each half has
// variance 2 v(i) about the same image (it averages half the passes).
struct SyntheticHalves {
  Image half0, half1;
  double variance = 0, relVariance = 0;  // the closed forms, over the values
};
SyntheticHalves syntheticHalves(int width, int height, std::uint64_t seed) {
  SyntheticHalves s;
  const std::size_t n = std::size_t(width) * height * 3;
  s.half0 = s.half1 = Image{width, height, 3, std::vector<float>(n)};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss;
  for (std::size_t i = 0; i < n; ++i) {
    const double mean = 0.2 + 2.0 * double(i % 97) / 97, v = 1e-4 * (1 + double(i % 13));
    s.half0.pixels[i] = float(mean + std::sqrt(2 * v) * gauss(rng));
    s.half1.pixels[i] = float(mean + std::sqrt(2 * v) * gauss(rng));
    s.variance += v / double(n);
    s.relVariance += v / (mean * mean + 0.01) / double(n);
  }
  return s;
}

TEST(ReferenceNoise, IsAQuarterOfTheHalvesMeanSquaredDifference) {
  // A constant difference d: exactly d^2 / 4.
  const Image a{2, 1, 3, {1, 1, 1, 2, 2, 2}}, b{2, 1, 3, {1.5f, 1.5f, 1.5f, 2.5f, 2.5f, 2.5f}};
  EXPECT_DOUBLE_EQ(referenceNoise(a, b).variance, 0.25 * 0.25);
  EXPECT_DOUBLE_EQ(referenceNoise(a, a).variance, 0);
  EXPECT_THROW(referenceNoise(a, Image{1, 1, 3, {0, 0, 0}}), std::invalid_argument);
}

TEST(ReferenceNoise, MatchesTheClosedFormOnGaussianHalves) {
  // 64 x 64 x 3 values: the estimate's relative standard error is about
  // sqrt(2 / 12288) = 1.3 %, so 6 % is over four of them.
  for (std::uint64_t seed : {1, 2, 3}) {
    const SyntheticHalves s = syntheticHalves(64, 64, seed);
    const ReferenceNoise noise = referenceNoise(s.half0, s.half1);
    EXPECT_NEAR(noise.variance, s.variance, 0.06 * s.variance) << seed;
    EXPECT_NEAR(noise.relVariance, s.relVariance, 0.06 * s.relVariance) << seed;
  }
}

// A diffuse sphere on a floor under a smooth, dim sky: every sample's
// contribution is bounded, so the variance estimates below concentrate (the
// default scene's sun makes a heavy tail, which 24 references do not tame).
std::string smoothSkyScene(const TempDir &tmp) {
  Image sky{32, 16, 3, std::vector<float>(32 * 16 * 3)};
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x)
      for (int c = 0; c < 3; ++c)
        sky.at(x, y, c) = float(0.5 + 0.4 * std::sin(0.2 * x + c) * std::cos(0.3 * y));
  writeImage((tmp / "sky.exr").string(), sky);
  return tmp.write("smooth.json", R"({
    "camera": {"eye": [0, 1.5, 4], "look_at": [0, 0.7, 0], "fov": 40},
    "film": {"width": 16, "height": 12},
    "environment": {"file": "sky.exr"},
    "materials": {"default": {"type": "lambertian", "albedo": [0.7, 0.7, 0.7]}},
    "meshes": [{"shape": "floor", "half_size": 10}, {"shape": "sphere", "center": [0, 1, 0],
                "radius": 1}]
  })");
}

// Rendered: the mean of many independent references' own estimates against
// the spread of those references about their mean, pixel by pixel: two
// unbiased estimates of the same variance.
TEST(ReferenceNoise, MatchesTheSpreadOfIndependentReferences) {
  TempDir tmp;
  const LoadedScene scene = loadScene(smoothSkyScene(tmp), tmp.path().string());
  ReferenceSettings s;
  s.spp = 8, s.passSpp = 4;
  s.render = scene.settings;
  s.render.integrator = IntegratorKind::Direct;
  constexpr int kReferences = 24;
  std::vector<Image> images;
  double estimate = 0;
  for (int k = 0; k < kReferences; ++k) {
    s.seed = 1000u * std::uint64_t(k + 1);  // passes seed, seed + 1: no two share one
    const ReferenceResult r =
        renderReference(scene.scene, "smooth", s, tmp / ("ref" + std::to_string(k)));
    ASSERT_TRUE(r.complete);
    images.push_back(r.image);
    estimate += r.noise.variance / kReferences;
  }
  double spread = 0;
  const std::size_t n = images[0].pixels.size();
  for (std::size_t i = 0; i < n; ++i) {
    double mean = 0, ss = 0;
    for (const Image &im : images) mean += im.pixels[i] / double(kReferences);
    for (const Image &im : images) ss += (im.pixels[i] - mean) * (im.pixels[i] - mean);
    spread += ss / (kReferences - 1) / double(n);
  }
  ASSERT_GT(spread, 0);
  EXPECT_NEAR(estimate / spread, 1.0, 0.15) << "estimate " << estimate << ", spread " << spread;
}

TEST(Baselines, ClassicBackendsAreThoseWithoutLearnedSets) {
  for (const char *word : {"independent", "random", "sobol", "halton", "sobol-tabulated"})
    EXPECT_TRUE(isClassicBackend(word)) << word;
  for (const char *word : {"optimized", "optimized-uniform", "optimized-bsdf+shift",
                           "optimized-both", "optimized:a.ptsb", "points:a.ptsb", "shifted:a.ptsb",
                           "neural", "neural:m.nuldnet", "no-such-word"})
    EXPECT_FALSE(isClassicBackend(word)) << word;
  EXPECT_FALSE(isClassicBackend("plugin:/some/libmine.so"));
  EXPECT_TRUE(isPluginBackend("plugin:/some/libmine.so:seed=3"));
  for (const char *word : {"sobol", "optimized", "neural", "no-such-word"})
    EXPECT_FALSE(isPluginBackend(word)) << word;
}

// A plugin row is scored against the best built-in classic row, never
// becomes it (even with the lowest MSE), and has no break-even: no setup.
TEST(Baselines, PluginRowsScoreAgainstTheBestClassicRow) {
  const std::vector<TimedRow> rows{{"s", "sobol", 16, 2.0, 0.1, 1.0, 0.0},
                                   {"s", "halton", 16, 3.0, 0.1, 1.0, 0.0},
                                   {"s", "plugin:/x/libmine.so", 16, 1.0, 0.1, 1.0, 0.0},
                                   {"s", "optimized", 16, 1.5, 0.1, 1.0, 2.0}};
  const std::vector<ClassicBaseline> c = classicBaselines(rows);
  for (const ClassicBaseline &b : c) EXPECT_EQ(b.backend, "sobol");
  EXPECT_NEAR(c[2].ratio.value, 0.5, 1e-12);
  EXPECT_TRUE(std::isnan(c[2].breakEven.value));
  EXPECT_NEAR(c[3].ratio.value, 0.75, 1e-12);
  EXPECT_FALSE(std::isnan(c[3].breakEven.value));
  EXPECT_TRUE(std::isnan(c[0].ratio.value));
}

// One row of a hand-made render.csv of scene "s".
struct HandRow {
  std::string backend;
  int spp;
  double mse, mseStderr, relmse, seconds, setupSeconds;
};
void addRow(CsvTable &table, const HandRow &r) {
  std::vector<std::string> row(renderStudyColumns().size());
  const auto set = [&](const char *column, const std::string &value) {
    row[table.column(column)] = value;
  };
  set("scene", "s");
  set("backend", r.backend);
  set("spp", std::to_string(r.spp));
  set("mse", formatNumber(r.mse));
  set("mse_stderr", formatNumber(r.mseStderr));
  set("relmse", formatNumber(r.relmse));
  set("seconds", formatNumber(r.seconds));
  set("setup_seconds", formatNumber(r.setupSeconds));
  table.addRow(row);
}

// A small study's CSV by hand: at 4 spp sobol-tabulated is the best classic
// (not sobol), and the learned rows' ratios, their standard errors and the
// flag follow from the numbers alone; at 16 spp sobol is the only classic.
TEST(Baselines, BestClassicRatioAndFlagByHandFromASmallStudy) {
  TempDir tmp;
  CsvTable table(tmp / "render.csv", renderStudyColumns(), renderStudyDerivedColumns());
  const auto add = [&](const std::string &backend, int spp, double mse, double stderr_) {
    addRow(table, {backend, spp, mse, stderr_, 2 * mse, 1, 0});
  };
  add("sobol", 4, 1.0, 0.1);
  add("halton", 4, 0.8, 0.08);
  add("sobol-tabulated", 4, 0.5, 0.05);
  add("independent", 4, 2.0, 0.2);
  add("optimized-both", 4, 0.4, 0.02);
  add("neural", 4, 0.6, 0.12);
  add("sobol", 16, 0.3, 0.03);
  add("optimized-both", 16, 0.15, 0.015);
  const ReferenceNoise noise{0.045, 0.2};
  fillBaselineColumns(table, {{"s", noise}});
  fillEqualTime(table, 1);

  const auto value = [&](std::size_t row, const char *column) {
    return table.rows()[row][table.column(column)];
  };
  const auto number = [&](std::size_t row, const char *column) {
    return parseNumber(value(row, column));
  };
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(value(i, "best_classic"), "sobol-tabulated");
  EXPECT_EQ(value(6, "best_classic"), "sobol");
  EXPECT_EQ(value(7, "best_classic"), "sobol");
  for (std::size_t i : {0, 1, 2, 3, 6})
    EXPECT_TRUE(std::isnan(number(i, "mse_ratio_best_classic"))) << "a classic row, " << i;
  // 0.4 / 0.5, relative errors 0.05 and 0.1 in quadrature.
  EXPECT_NEAR(number(4, "mse_ratio_best_classic"), 0.8, 1e-6);
  EXPECT_NEAR(number(4, "mse_ratio_best_classic_stderr"), 0.8 * std::sqrt(0.0025 + 0.01), 1e-6);
  EXPECT_NEAR(number(5, "mse_ratio_best_classic"), 1.2, 1e-6);
  EXPECT_NEAR(number(5, "mse_ratio_best_classic_stderr"), 1.2 * std::sqrt(0.04 + 0.01), 1e-6);
  EXPECT_NEAR(number(7, "mse_ratio_best_classic"), 0.5, 1e-6);
  EXPECT_NEAR(number(7, "mse_ratio_best_classic_stderr"), 0.5 * std::sqrt(0.02), 1e-6);

  // Less the reference's noise, and flagged below 10 x 0.045.
  EXPECT_NEAR(number(0, "mse_less_reference"), 0.955, 1e-6);
  EXPECT_NEAR(number(0, "relmse_less_reference"), 1.8, 1e-6);
  const std::vector<std::string> flagged{"0", "0", "0", "0", "1", "0", "1", "1"};
  for (std::size_t i = 0; i < flagged.size(); ++i)
    EXPECT_EQ(value(i, "reference_too_noisy"), flagged[i]) << i;

  // The verdicts: optimized-both wins both spp, at its MSE ratio above.
  CsvTable verdicts(tmp / "verdicts.csv", verdictColumns());
  verdicts.loadExisting();
  ASSERT_EQ(verdicts.rows().size(), 2u);
  const auto verdict = [&](std::size_t row, const char *column) {
    return verdicts.rows()[row][verdicts.column(column)];
  };
  EXPECT_EQ(verdict(0, "best"), "optimized-both");
  EXPECT_EQ(verdict(0, "best_classic"), "sobol-tabulated");
  EXPECT_NEAR(parseNumber(verdict(0, "mse_ratio_best_classic")), 0.8, 1e-6);
  EXPECT_NEAR(parseNumber(verdict(0, "mse_ratio_best_classic_stderr")),
              0.8 * std::sqrt(0.0025 + 0.01), 1e-6);
  EXPECT_EQ(verdict(1, "best_classic"), "sobol");

  // A scene without a recorded reference: no correction, no flag.
  fillBaselineColumns(table, {});
  EXPECT_TRUE(std::isnan(number(4, "mse_less_reference")));
  EXPECT_EQ(value(4, "reference_too_noisy"), "0");
}

// break_even_renders by hand: the smallest K with MSE x (seconds + setup /
// K) below the best classic row's, each paying its own setup.
TEST(Baselines, BreakEvenRendersByHand) {
  const auto row = [](double mse, double stderr_, double seconds, double setup) {
    TimedRow r;
    r.scene = "s", r.spp = 16, r.mse = mse, r.mseStderr = stderr_;
    r.seconds = seconds, r.setupSeconds = setup;
    return r;
  };
  const TimedRow classic = row(1.0, 0.01, 2.0, 0.5);
  // Finite: gain 1 x 2 - 0.5 x 2.2 = 0.9 per render, extra setup 0.5 x 30 -
  // 1 x 0.5 = 14.5; crossing at 16.11, so K = 17 (K = 16 still loses:
  // 0.5 (2.2 + 30 / 16) = 2.0375 > 1 x (2 + 0.5 / 16) = 2.03125).
  const TimedRow learned = row(0.5, 0.01, 2.2, 30);
  const Ratio k = breakEvenRenders(learned, classic);
  EXPECT_EQ(k.value, 17);
  EXPECT_GT(0.5 * (2.2 + 30.0 / 16), 1.0 * (2 + 0.5 / 16));
  EXPECT_LT(0.5 * (2.2 + 30.0 / 17), 1.0 * (2 + 0.5 / 17));
  // Its standard error by the delta method, against finite differences.
  const auto crossing = [&](double m, double b) {
    return (m * 30 - b * 0.5) / (b * 2.0 - m * 2.2);
  };
  const double h = 1e-6, dm = (crossing(0.5 + h, 1.0) - crossing(0.5 - h, 1.0)) / (2 * h),
               db = (crossing(0.5, 1.0 + h) - crossing(0.5, 1.0 - h)) / (2 * h);
  EXPECT_NEAR(k.stderr_, std::hypot(dm * 0.01, db * 0.01), 1e-6);
  // Setup cheaper than the classic's and ahead per render: the first render.
  EXPECT_EQ(breakEvenRenders(row(0.5, 0.01, 2.0, 0.1), classic).value, 1);
  // Never ahead per render: infinity, whatever its setup...
  const TimedRow sobol = row(1.0, 0.01, 2.0, 0.0);
  EXPECT_TRUE(std::isinf(breakEvenRenders(row(1.2, 0.01, 2.0, 0.0), sobol).value));
  EXPECT_TRUE(std::isinf(breakEvenRenders(row(0.5, 0.01, 4.5, 10), classic).value));
  // ... unless the classic row's own setup makes it lose the first render
  // (1.2 x 2 < 1 x (2 + 0.5)).
  EXPECT_EQ(breakEvenRenders(row(1.2, 0.01, 2.0, 0.0), classic).value, 1);
  // A tie within standard errors: gain 1 x 2 - 0.95 x 2 = 0.1 against a
  // standard error of hypot(2 x 0.1, 2 x 0.1) = 0.28: K is finite but its
  // standard error is infinite.
  const Ratio tie = breakEvenRenders(row(0.95, 0.1, 2.0, 5), row(1.0, 0.1, 2.0, 0.5));
  EXPECT_EQ(tie.value, std::floor((0.95 * 5 - 0.5) / 0.1) + 1);
  EXPECT_TRUE(std::isinf(tie.stderr_));
}

// The column from a study's CSV: a learned row's break_even_renders against
// its best classic row, a classic row's NaN, and the verdict's the same.
TEST(Baselines, BreakEvenRendersColumnsFromACsv) {
  TempDir tmp;
  CsvTable table(tmp / "render.csv", renderStudyColumns(), renderStudyDerivedColumns());
  const auto add = [&](const std::string &backend, double mse, double seconds, double setup) {
    addRow(table, {backend, 16, mse, mse / 100, mse, seconds, setup});
  };
  add("sobol", 1.0, 2.0, 0);
  add("optimized", 0.5, 2.0, 10);  // gain 1 per render: K > 5, so 6
  add("neural", 1.5, 1.0, 0);      // gain 0.5 per render, no setup: K = 1
  fillBaselineColumns(table, {});
  fillEqualTime(table, 1);
  const auto number = [&](std::size_t row, const char *column) {
    return parseNumber(table.rows()[row][table.column(column)]);
  };
  EXPECT_TRUE(std::isnan(number(0, "break_even_renders")));
  EXPECT_EQ(number(1, "break_even_renders"), 6);
  EXPECT_EQ(number(2, "break_even_renders"), 1);
  CsvTable verdicts(tmp / "verdicts.csv", verdictColumns());
  verdicts.loadExisting();
  ASSERT_EQ(verdicts.rows().size(), 1u);
  EXPECT_EQ(verdicts.rows()[0][verdicts.column("best")], "neural");
  EXPECT_EQ(parseNumber(verdicts.rows()[0][verdicts.column("break_even_renders")]), 1);
}

TEST(Baselines, RatioOfMeansPropagatesRelativeErrors) {
  const Ratio q = ratioOfMeans(1.0, 0.1, 2.0, 0.1);
  EXPECT_DOUBLE_EQ(q.value, 0.5);
  EXPECT_NEAR(q.stderr_, 0.5 * std::sqrt(0.01 + 0.0025), 1e-15);
  EXPECT_NEAR(ratioOfMeans(1.0, NAN, 2.0, 0.1).stderr_, 0.5 * 0.05, 1e-15) << "one repeat";
  EXPECT_TRUE(std::isnan(ratioOfMeans(1.0, 0.1, 0.0, 0.1).value));
}

}  // namespace
}  // namespace nuld::study
