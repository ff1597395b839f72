// The mean chamfer distance between the instances of a point-set file.

#include "sampler/metrics/set_distance.h"

#include <gtest/gtest.h>

#include <stdexcept>

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

}  // namespace
}  // namespace nuld
