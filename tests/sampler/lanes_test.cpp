// The vector helpers of the soft box loss against scalar libm and std::.
#include "sampler/loss/lanes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace nuld::lanes {
namespace {

TEST(Lanes, ExpMatchesLibmToAFewUlps) {
  double worst = 0;
  constexpr int kSteps = 1400000;
  for (int i = 0; i <= kSteps; i += kWidth) {
    Doubles x;
    for (int j = 0; j < kWidth; ++j)
      x[j] = -700.0 + 1400.0 * double(std::min(i + j, kSteps)) / kSteps;
    const Doubles e = exp(x);
    for (int j = 0; j < kWidth; ++j) {
      const double ref = std::exp(x[j]);
      worst = std::max(worst, std::abs(e[j] - ref) / ref);
    }
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_EQ(exp(broadcast(0.0))[0], 1.0);
}

TEST(Lanes, ExpClampsInsteadOfOverflowing) {
  const Doubles e = exp(broadcast(-std::numeric_limits<double>::infinity()));
  EXPECT_NEAR(e[0] / std::exp(-700.0), 1.0, 1e-15);  // the bound's value, not 0 or NaN
  EXPECT_NEAR(exp(broadcast(1e300))[kWidth - 1] / std::exp(700.0), 1.0, 1e-15);
  EXPECT_NEAR(exp(broadcast(-1e300))[0] / std::exp(-700.0), 1.0, 1e-15);
}

TEST(Lanes, MinMaxAbsFollowTheScalarRules) {
  Doubles a = broadcast(1.0), b = broadcast(2.0);
  a[0] = -0.0;
  b[0] = 0.0;  // equal: min and max return their first argument, as std::
  EXPECT_TRUE(std::signbit(min(a, b)[0]));
  EXPECT_TRUE(std::signbit(max(a, b)[0]));
  EXPECT_EQ(min(a, b)[kWidth - 1], 1.0);
  EXPECT_EQ(max(a, b)[kWidth - 1], 2.0);
  EXPECT_EQ(abs(broadcast(-3.5))[0], 3.5);
  EXPECT_FALSE(std::signbit(abs(broadcast(-0.0))[0]));
  EXPECT_TRUE(std::signbit(broadcast(-0.0)[kWidth - 1]));
}

TEST(Lanes, SumFirstLanesCompressPermute) {
  Doubles v;
  for (int j = 0; j < kWidth; ++j) v[j] = double(j + 1);
  EXPECT_EQ(sum(v), kWidth * (kWidth + 1) / 2.0);
  for (int n = 0; n <= kWidth; ++n) {
    const Mask m = firstLanes(n);
    for (int j = 0; j < kWidth; ++j) EXPECT_EQ(m[j] != 0, j < n);
  }
  const Mask all = firstLanes(kWidth + 5);  // a count past the vector sets every lane
  for (int j = 0; j < kWidth; ++j) EXPECT_NE(all[j], 0);
  // Every other lane, kept in order.
  Mask odd;
  for (int j = 0; j < kWidth; ++j) odd[j] = (j % 2) ? -1 : 0;
  double out[kWidth];
  ASSERT_EQ(compress(odd, v, out), kWidth / 2);
  for (int j = 0; j < kWidth / 2; ++j) EXPECT_EQ(out[j], double(2 * j + 2));
  // A table of 8 read backwards.
  const double table[8] = {10, 11, 12, 13, 14, 15, 16, 17};
  Mask reversed;
  for (int j = 0; j < kWidth; ++j) reversed[j] = 7 - j;
  const Doubles r = lookup8(table, reversed);
  for (int j = 0; j < kWidth; ++j) EXPECT_EQ(r[j], 17.0 - j);
}

}  // namespace
}  // namespace nuld::lanes
