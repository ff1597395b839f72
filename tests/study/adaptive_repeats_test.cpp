// planRepeats (tools/study/adaptive_repeats.h): which rows need more repeats
// for their ratios to reach the target, by how many, and within the budget.
#include "tools/study/adaptive_repeats.h"

#include <gtest/gtest.h>

#include <cmath>

namespace nuld::study {
namespace {

TimedRow row(const std::string &backend, double mse, double stderr_, std::size_t spp = 16,
             const std::string &scene = "s") {
  return {scene, backend, spp, mse, stderr_, 1.0, 0.0};
}

TEST(AdaptiveRepeats, WithoutATargetTheRepeatsStand) {
  const std::vector<TimedRow> rows = {row("sobol", 1, 0.5), row("optimized", 0.5, 0.5)};
  const RepeatPlan p = planRepeats(rows, {8, 8}, RepeatBudget{});
  EXPECT_EQ(p.want, (std::vector<std::size_t>{8, 8}));
  EXPECT_EQ(p.decided, (std::vector<bool>{true, true}));
}

TEST(AdaptiveRepeats, AWideRatioGrowsBothItsRowsByTheSquaredExcess) {
  // optimized / sobol = 0.8 with relative error sqrt(0.1^2 + 0.05^2) = 0.112:
  // (0.112 / 0.05)^2 x 1.1 = 5.5 times the repeats, clamped to 4 times.
  const std::vector<TimedRow> rows = {row("sobol", 1, 0.05), row("optimized", 0.8, 0.08)};
  RepeatBudget b;
  b.targetStderr = 0.05;
  b.maxRepeats = 1000;
  const RepeatPlan p = planRepeats(rows, {8, 8}, b);
  EXPECT_TRUE(p.decided[0]) << "sobol is the best classic row and itself: no ratio";
  EXPECT_FALSE(p.decided[1]);
  EXPECT_NEAR(p.worstStderr[1], std::hypot(0.1, 0.05), 1e-12);
  EXPECT_EQ(p.want[1], 32u);
  EXPECT_EQ(p.want[0], 32u) << "the baseline of an undecided ratio grows with it";

  // A ratio just above the target still at least doubles; the cap holds.
  const std::vector<TimedRow> near = {row("sobol", 1, 0.03), row("optimized", 1, 0.042)};
  b.maxRepeats = 12;
  const RepeatPlan q = planRepeats(near, {8, 8}, b);
  EXPECT_FALSE(q.decided[1]);
  EXPECT_EQ(q.want[1], 12u);
  EXPECT_EQ(q.want[0], 12u);
}

TEST(AdaptiveRepeats, DecidedRatiosAndOtherScenesAreLeftAlone) {
  RepeatBudget b;
  b.targetStderr = 0.05;
  // Each row is compared with the best classic row (halton here) and sobol.
  const std::vector<TimedRow> rows = {row("sobol", 1.0, 0.01), row("halton", 0.9, 0.01),
                                      row("optimized", 0.7, 0.01), row("sobol", 1.0, 0.3, 64),
                                      row("optimized", 0.5, 0.01, 16, "other")};
  const RepeatPlan p = planRepeats(rows, {8, 8, 8, 8, 8}, b);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(p.decided[i]) << i;
    EXPECT_EQ(p.want[i], 8u) << i;
  }
  // Alone at its spp and scene: nothing to compare with.
  EXPECT_TRUE(p.decided[3]);
  EXPECT_TRUE(p.decided[4]);
  EXPECT_EQ(p.worstStderr[3], 0);
}

TEST(AdaptiveRepeats, OneRepeatSaysNothingOfTheNoise) {
  RepeatBudget b;
  b.targetStderr = 0.05;
  const std::vector<TimedRow> rows = {row("sobol", 1, 0), row("independent", 2, 0)};
  const RepeatPlan p = planRepeats(rows, {1, 1}, b);
  EXPECT_FALSE(p.decided[1]);
  EXPECT_TRUE(std::isinf(p.worstStderr[1]));
  EXPECT_EQ(p.want[1], 8u) << "four times max(1, 2)";
  EXPECT_EQ(p.want[0], 8u);
}

TEST(AdaptiveRepeats, StopsHaveTheirNames) {
  EXPECT_STREQ(stopName(RepeatStop::Fixed), "fixed");
  EXPECT_STREQ(stopName(RepeatStop::Precision), "precision");
  EXPECT_STREQ(stopName(RepeatStop::Budget), "budget");
}

}  // namespace
}  // namespace nuld::study
