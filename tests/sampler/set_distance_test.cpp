// How the instances of a point-set file differ: the mean chamfer distance
// between them, and the spread of their means.

#include "sampler/metrics/set_distance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "sampler/metrics/moment_spread.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"

namespace nuld {
namespace {

TEST(SetDistance, ZeroForCopiesAndMatchesABruteForceCase) {
  PointSet same;
  same.n = 3;
  same.points = {{0.1, 0.1}, {0.5, 0.5}, {0.9, 0.2}, {0.1, 0.1}, {0.5, 0.5}, {0.9, 0.2}};
  EXPECT_EQ(meanSetDistance(same), 0);
  PointSet two;
  two.n = 2;
  // Set B is set A moved by 0.1 in x: every nearest neighbour is 0.1 away.
  two.points = {{0.2, 0.2}, {0.7, 0.6}, {0.3, 0.2}, {0.8, 0.6}};
  EXPECT_NEAR(meanSetDistance(two), 0.1, 1e-15);
  PointSet one;
  one.n = 2;
  one.points = {{0.2, 0.2}, {0.7, 0.6}};
  EXPECT_THROW(meanSetDistance(one), std::invalid_argument);
}

// The spread of the means: by hand for two sets (sample standard deviation
// of two values a, b is |a - b| / sqrt 2); for independent uniform sets the
// closed form sqrt(1 / (12 N)) in x and y (x y: sqrt((1/9 - 1/16) / N));
// Owen-scrambled Sobol sets far below it.
TEST(MomentSpread, MatchesByHandAndClosedForms) {
  PointSet two;
  two.n = 2;
  two.points = {{0.2, 0.4}, {0.6, 0.4}, {0.3, 0.5}, {0.7, 0.9}};  // means (0.4, 0.4), (0.5, 0.7)
  const MomentSpread s = momentSpread(two);
  EXPECT_NEAR(s.x, 0.1 / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(s.y, 0.3 / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(s.xy, std::abs((0.08 + 0.24) / 2 - (0.15 + 0.63) / 2) / std::sqrt(2.0), 1e-15);

  constexpr std::size_t kN = 16, kSets = 2000;
  PointSet uniform;
  uniform.n = kN;
  Rng rng(5);
  for (std::size_t i = 0; i < kN * kSets; ++i)
    uniform.points.push_back({rng.uniform(), rng.uniform()});
  const MomentSpread u = momentSpread(uniform);
  EXPECT_NEAR(u.x, std::sqrt(1.0 / (12 * kN)), 0.05 * std::sqrt(1.0 / (12 * kN)));
  EXPECT_NEAR(u.y, std::sqrt(1.0 / (12 * kN)), 0.05 * std::sqrt(1.0 / (12 * kN)));
  EXPECT_NEAR(u.xy, std::sqrt((1.0 / 9 - 1.0 / 16) / kN),
              0.05 * std::sqrt((1.0 / 9 - 1.0 / 16) / kN));
  const MomentSpread owen =
      momentSpread(generatePointSet({SequenceKind::Sobol, Scramble::Owen, 3}, kN, 200));
  EXPECT_LT(owen.x, 0.2 * u.x);
  EXPECT_LT(owen.y, 0.2 * u.y);
  EXPECT_THROW(momentSpread(generatePointSet({SequenceKind::Sobol, Scramble::Owen, 3}, kN, 1)),
               std::invalid_argument);
}

}  // namespace
}  // namespace nuld
