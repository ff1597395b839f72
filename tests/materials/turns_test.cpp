// The turn-unit trigonometry against long double: sinCosTurns within 2e-16
// over [0, 1] (where samplers call it), exact at the quarter turns and fine
// beyond [0, 1]; atan2Turns within 2e-16 turns in every octant, at the
// reduction's centres, for tiny and huge vectors, and inside [0, 1].

#include "materials/turns.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sampler/sequences/rng.h"

namespace nuld {
namespace {

constexpr long double kTwoPi = 6.283185307179586476925286766559005768L;

void expectClose(double t, double tolerance) {
  const SinCos v = sinCosTurns(t);
  const long double angle = kTwoPi * static_cast<long double>(t);
  EXPECT_NEAR(v.sin, double(sinl(angle)), tolerance) << "t " << t;
  EXPECT_NEAR(v.cos, double(cosl(angle)), tolerance) << "t " << t;
}

TEST(SinCosTurns, MatchesLongDoubleOverTheUnitInterval) {
  Rng rng(5);
  for (int i = 0; i < 200000; ++i) expectClose(rng.uniform(), 2e-16);
  // Around the quarter-turn boundaries, where the reduction switches.
  for (double q : {0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0})
    for (double d : {-1e-9, -1e-16, 0.0, 1e-16, 1e-9}) expectClose(q + d, 2e-16);
  expectClose(1e-300, 1e-300);
  expectClose(std::nextafter(1.0, 0.0), 2e-16);
}

TEST(SinCosTurns, QuarterTurnsAreExact) {
  const SinCos q0 = sinCosTurns(0), q1 = sinCosTurns(0.25), q2 = sinCosTurns(0.5),
               q3 = sinCosTurns(0.75), q4 = sinCosTurns(1);
  EXPECT_TRUE(q0.sin == 0 && q0.cos == 1);
  EXPECT_TRUE(q1.sin == 1 && q1.cos == 0);
  EXPECT_TRUE(q2.sin == 0 && q2.cos == -1);
  EXPECT_TRUE(q3.sin == -1 && q3.cos == 0);
  EXPECT_TRUE(q4.sin == 0 && q4.cos == 1);
}

TEST(SinCosTurns, AnyFiniteTurnCount) {
  Rng rng(6);
  for (int i = 0; i < 20000; ++i) {
    const double t = 200 * rng.uniform() - 100;
    // The angle 2 pi t itself carries t's rounding, |t| ulp ~ 1.4e-14 here.
    expectClose(t, 1e-13);
    const SinCos v = sinCosTurns(t);
    EXPECT_NEAR(v.sin * v.sin + v.cos * v.cos, 1, 4e-16);
  }
}

long double referenceTurns(double y, double x) {
  long double t = atan2l(y, x) / kTwoPi;
  return t < 0 ? t + 1 : t;
}

TEST(Atan2Turns, MatchesLongDoubleInEveryOctant) {
  Rng rng(7);
  for (int i = 0; i < 200000; ++i) {
    const double x = 2 * rng.uniform() - 1, y = 2 * rng.uniform() - 1;
    ASSERT_NEAR(atan2Turns(y, x), double(referenceTurns(y, x)), 2e-16) << y << " " << x;
  }
  // Axes, diagonals, the reduction's centres and the octant edges.
  for (int k = 0; k < 64; ++k) {
    const SinCos d = sinCosTurns(k / 64.0);
    for (double s : {1.0, 1e-300, 1e300}) {
      const double y = s * d.sin, x = s * d.cos, expected = double(referenceTurns(y, x));
      EXPECT_NEAR(atan2Turns(y, x), expected, 2e-16) << k;
    }
  }
  for (double j = 0; j <= 16; ++j) {
    EXPECT_NEAR(atan2Turns(j / 16, 1), double(referenceTurns(j / 16, 1)), 2e-16) << j;
    EXPECT_NEAR(atan2Turns(1, j / 16), double(referenceTurns(1, j / 16)), 2e-16) << j;
  }
}

TEST(Atan2Turns, StaysInTheUnitIntervalAtItsEdges) {
  EXPECT_EQ(atan2Turns(0, 0), 0);
  EXPECT_EQ(atan2Turns(0, 1), 0);
  EXPECT_EQ(atan2Turns(-0.0, 1), 0);
  EXPECT_EQ(atan2Turns(0, -1), 0.5);
  EXPECT_EQ(atan2Turns(1, 0), 0.25);
  EXPECT_EQ(atan2Turns(-1, 0), 0.75);
  const double below = atan2Turns(-1e-300, 1);  // just below the seam
  EXPECT_TRUE(below >= 0 && below <= 1) << below;
  EXPECT_GT(atan2Turns(-1e-10, 1), 0.99);
}

}  // namespace
}  // namespace nuld
