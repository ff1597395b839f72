// wrapToDomain: the square clamps; the sphere and hemisphere take a point
// through the poles as often as it crossed one, with longitude periodic.

#include <gtest/gtest.h>

#include "sampler/point.h"

namespace nuld {
namespace {

TEST(WrapToDomain, SquareClamps) {
  double s = 0;
  Point2 p = wrapToDomain({1.25, -0.25}, Domain::Square, &s);
  EXPECT_LT(p.x, 1);
  EXPECT_GT(p.x, 0.999999);
  EXPECT_EQ(p.y, 0);
  EXPECT_EQ(s, 1);
  p = wrapToDomain({0.3, 0.7}, Domain::Square);
  EXPECT_EQ(p, (Point2{0.3, 0.7}));
}

TEST(WrapToDomain, SpherePassesThroughThePoles) {
  for (Domain d : {Domain::Sphere, Domain::Hemisphere}) {
    double s = 0;
    // Past the south pole: the opposite meridian, heading north.
    Point2 p = wrapToDomain({0.1, 1.3}, d, &s);
    EXPECT_DOUBLE_EQ(p.x, 0.6);
    EXPECT_DOUBLE_EQ(p.y, 0.7);
    EXPECT_EQ(s, -1);
    // Past the north pole.
    p = wrapToDomain({0.8, -0.2}, d, &s);
    EXPECT_DOUBLE_EQ(p.x, 0.3);
    EXPECT_DOUBLE_EQ(p.y, 0.2);
    EXPECT_EQ(s, -1);
    // Two crossings: back on the own meridian.
    p = wrapToDomain({0.4, 2.25}, d, &s);
    EXPECT_DOUBLE_EQ(p.x, 0.4);
    EXPECT_DOUBLE_EQ(p.y, 0.25);
    EXPECT_EQ(s, 1);
    // Exactly at a pole stays inside [0, 1).
    p = wrapToDomain({0.2, 1.0}, d);
    EXPECT_LT(p.y, 1);
    for (double v = -3; v <= 3; v += 0.01) {
      p = wrapToDomain({7.3, v}, d);
      EXPECT_TRUE(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1) << v;
    }
  }
}

}  // namespace
}  // namespace nuld
