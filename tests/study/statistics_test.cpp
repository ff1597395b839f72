// The studies' summaries of repeats (tools/study/statistics.h), by hand: a
// render cell's repeats split into render seconds and one-time setup, and
// their median with its spread.
#include "tools/study/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace nuld::study {
namespace {

// The first repeat made banks for 0.5 s (the others found them): that is
// setup, and every repeat's render seconds are what is left.
TEST(RepeatSeconds, SetsMadeWhilePreparingAreSetup) {
  const std::vector<double> whole{1.52, 1.02, 1.11}, made{0.5, 0, 0};
  const RepeatSeconds s = splitRepeatSeconds(whole, made);
  ASSERT_EQ(s.render.size(), 3u);
  EXPECT_NEAR(s.render[0], 1.02, 1e-12);
  EXPECT_EQ(s.render[1], 1.02);
  EXPECT_EQ(s.render[2], 1.11);
  EXPECT_EQ(s.setup, 0.5);
}

// A backend that makes nothing as it prepares keeps its seconds exactly, so
// a cell whose sets were found keeps a setup of 0; no repeats give nothing.
TEST(RepeatSeconds, NothingMadeMovesNothing) {
  const std::vector<double> whole{2.0, 2.5}, made{0, 0};
  const RepeatSeconds s = splitRepeatSeconds(whole, made);
  EXPECT_EQ(s.render, whole);
  EXPECT_EQ(s.setup, 0);
  EXPECT_TRUE(splitRepeatSeconds({}, {}).render.empty());
}

// Median, median absolute deviation and the median's error worked by hand;
// one repeat slowed threefold by other work moves the median by one rank
// where it pulls the mean towards itself.
TEST(MedianAndSpread, ByHandAndUnmovedByOneSlowRepeat) {
  const std::vector<double> odd{1.0, 1.2, 0.9, 3.0, 1.1};  // sorted: 0.9 1.0 1.1 1.2 3.0
  const MedianAndSpread m = medianAndSpread(odd);
  EXPECT_DOUBLE_EQ(m.median, 1.1);
  // |x - 1.1|: 0.1 0.1 0.2 0.1 1.9, sorted 0.1 0.1 0.1 0.2 1.9.
  EXPECT_NEAR(m.mad, 0.1, 1e-12);
  // The error from the sample deviation, which the slow repeat widens.
  EXPECT_NEAR(meanAndError(odd).mean, 1.44, 1e-12);
  double ss = 0;
  for (double x : odd) ss += (x - 1.44) * (x - 1.44);
  EXPECT_NEAR(m.stderr_, 1.2533 * std::sqrt(ss / 4 / 5), 1e-12);

  // Load that came and went: five quick repeats and three slow. The median
  // sits among the quick ones with a small MAD; the error sees both.
  const std::vector<double> bimodal{0.8, 0.63, 0.44, 0.32, 0.33, 0.36, 0.33, 0.35};
  const MedianAndSpread b = medianAndSpread(bimodal);
  EXPECT_NEAR(b.median, 0.355, 1e-12);
  EXPECT_LT(b.mad, 0.05);
  EXPECT_GT(b.stderr_ / b.median, 0.15);

  const std::vector<double> even{4.0, 1.0, 3.0, 2.0};
  EXPECT_DOUBLE_EQ(medianAndSpread(even).median, 2.5);
  EXPECT_DOUBLE_EQ(medianAndSpread(even).mad, 1.0);  // 1.5 0.5 0.5 1.5

  const std::vector<double> one{0.7};
  EXPECT_EQ(medianAndSpread(one).median, 0.7);
  EXPECT_EQ(medianAndSpread(one).mad, 0);
  EXPECT_EQ(medianAndSpread(one).stderr_, 0);
  EXPECT_EQ(medianAndSpread({}).median, 0);
}

}  // namespace
}  // namespace nuld::study
