#include "sampler/loss/fast_exp.h"

#include <gtest/gtest.h>

#include <cmath>

namespace nuld {
namespace {

TEST(FastExp, MatchesLibmToAFewUlps) {
  double worst = 0;
  for (int i = 0; i <= 2000000; ++i) {
    const double x = -700.0 * i / 2000000.0;
    const double ref = std::exp(x);
    worst = std::max(worst, std::abs(fastExpNonPositive(x) - ref) / ref);
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_EQ(fastExpNonPositive(0.0), 1.0);
  EXPECT_GT(fastExpNonPositive(-1e300), 0.0);
  EXPECT_TRUE(std::isfinite(fastExpNonPositive(-INFINITY)));
}

}  // namespace
}  // namespace nuld
