// The studies' summaries of repeats (tools/study/statistics.h), by hand: a
// render cell's repeats split into render seconds and one-time setup.
#include "tools/study/statistics.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace nuld::study
