// Convergence rates (tools/study/convergence.h): the weighted slope of log
// error over log spp against exact power laws, its standard error against
// the spread of slopes fitted to simulated repeats, the unweighted fallback
// against the textbook formula, and slopes.csv's rows from a hand-made table.
#include "tools/study/convergence.h"

#include <gtest/gtest.h>

#include <random>

#include "tests/common/temp_dir.h"
#include "tools/study/render_study.h"

namespace nuld::study {
namespace {

using test::TempDir;

TEST(ConvergenceSlope, ExactPowerLawsGiveTheirExponent) {
  const std::vector<double> spp{4, 16, 64, 256};
  for (const double rate : {-1.0, -1.5, -2.0}) {
    std::vector<double> mse, se;
    for (const double n : spp) mse.push_back(3 * std::pow(n, rate)), se.push_back(0.1 * mse.back());
    const Ratio s = convergenceSlope(spp, mse, se);
    EXPECT_NEAR(s.value, rate, 1e-12);
    // Equal relative errors 0.1: weights 100, sum (x - mean x)^2 = 5 ln(4)^2.
    EXPECT_NEAR(s.stderr_, std::sqrt(1 / (100 * 5 * std::pow(std::log(4.0), 2))), 1e-12);
  }
}

// Simulated studies: each point's log error drawn around the law with the
// standard deviation its stated error implies. The slopes' mean is the law's
// and their spread the stated standard error.
TEST(ConvergenceSlope, StandardErrorMatchesTheSpreadOfFits) {
  const std::vector<double> spp{4, 16, 64};
  const std::vector<double> relative{0.05, 0.1, 0.2};  // unequal weights
  std::mt19937_64 rng(3);
  std::normal_distribution<double> z;
  double sum = 0, sum2 = 0, stated = 0;
  constexpr int kStudies = 20000;
  for (int k = 0; k < kStudies; ++k) {
    std::vector<double> mse, se;
    for (std::size_t i = 0; i < spp.size(); ++i) {
      mse.push_back(std::pow(spp[i], -1.2) * std::exp(relative[i] * z(rng)));
      se.push_back(relative[i] * mse.back());
    }
    const Ratio s = convergenceSlope(spp, mse, se);
    sum += s.value, sum2 += s.value * s.value, stated += s.stderr_;
  }
  const double mean = sum / kStudies, spread = std::sqrt(sum2 / kStudies - mean * mean);
  stated /= kStudies;
  EXPECT_NEAR(mean, -1.2, 4 * spread / std::sqrt(double(kStudies)));
  EXPECT_NEAR(spread / stated, 1.0, 0.05);
}

TEST(ConvergenceSlope, UnweightedFallbackAndRefusals) {
  // No standard errors (one repeat): ordinary least squares, its standard
  // error from the residuals over n - 2 degrees of freedom.
  const std::vector<double> spp{1, 2, 4, 8}, mse{1.0, 0.6, 0.2, 0.15}, none(4, 0.0);
  double mx = 0, my = 0;
  std::vector<double> x, y;
  for (std::size_t i = 0; i < 4; ++i) {
    x.push_back(std::log(spp[i])), y.push_back(std::log(mse[i]));
    mx += x.back() / 4, my += y.back() / 4;
  }
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < 4; ++i)
    sxx += (x[i] - mx) * (x[i] - mx), sxy += (x[i] - mx) * (y[i] - my);
  const double b = sxy / sxx;
  double rss = 0;
  for (std::size_t i = 0; i < 4; ++i) rss += std::pow(y[i] - my - b * (x[i] - mx), 2);
  const Ratio s = convergenceSlope(spp, mse, none);
  EXPECT_NEAR(s.value, b, 1e-12);
  EXPECT_NEAR(s.stderr_, std::sqrt(rss / 2 / sxx), 1e-12);
  // Too few points, a zero error, one spp repeated.
  EXPECT_TRUE(std::isnan(convergenceSlope(std::vector<double>{4, 16}, std::vector<double>{1, 0.5},
                                          std::vector<double>{0.1, 0.1})
                             .value));
  EXPECT_TRUE(std::isnan(convergenceSlope(spp, std::vector<double>{1, 0, 0.2, 0.1}, none).value));
  EXPECT_TRUE(
      std::isnan(convergenceSlope(std::vector<double>{4, 4, 4}, std::vector<double>{1, 1, 1},
                                  std::vector<double>{0.1, 0.1, 0.1})
                     .value));
}

// slopes.csv: a row per scene and backend with three or more spp values, in
// the table's order; a backend with two is left out.
TEST(ConvergenceSlope, RowsOfAStudyTable) {
  TempDir tmp;
  CsvTable table(tmp / "render.csv", renderStudyColumns(), renderStudyDerivedColumns());
  const auto add = [&](const std::string &backend, int spp, double mse, double screen) {
    std::vector<std::string> row(table.columns().size());
    const auto set = [&](const char *c, const std::string &v) { row[table.column(c)] = v; };
    set("scene", "s"), set("backend", backend), set("spp", std::to_string(spp));
    set("mse", formatNumber(mse)), set("mse_stderr", formatNumber(0.1 * mse));
    set("screen_mse", formatNumber(screen)), set("screen_mse_stderr", formatNumber(0.1 * screen));
    table.addRow(row);
  };
  for (const int n : {16, 4, 64}) add("sobol", n, std::pow(n, -1.5), std::pow(n, -2.0));
  for (const int n : {4, 16}) add("halton", n, 1.0 / n, 1.0 / n);
  const auto rows = slopeRows(table);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0][1], "sobol");
  EXPECT_EQ(rows[0][2], "4 16 64");
  EXPECT_NEAR(parseNumber(rows[0][3]), -1.5, 1e-6);
  EXPECT_NEAR(parseNumber(rows[0][5]), -2.0, 1e-6);
  EXPECT_EQ(rows[0].size(), slopeColumns().size());
}

}  // namespace
}  // namespace nuld::study
