// pmj02: every prefix and aligned block is a (0,2)-net, raw and randomized,
// against a brute-force interval counter (its control: Owen-Sobol's sets).
#include "sampler/sequences/pmj02.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "sampler/sequences/sequence.h"
#include "tests/sampler/classic_set_oracles.h"

namespace nuld {
namespace {

using test::sequenceNetFailure;

// The oracle first: Owen-Sobol's dimensions (0, 1) are a (0,2)-sequence, so
// it must pass them; a set with one point moved must fail.
TEST(Pmj02, NetOracleAcceptsSobolAndRejectsAMovedPoint) {
  std::vector<Point2> sobol(1024);
  generateSet({SequenceKind::Sobol, Scramble::Owen, 5}, 0, sobol);
  EXPECT_EQ(sequenceNetFailure(sobol, true), "");
  std::vector<Point2> broken = pmj02Sequence(3, 6);
  ASSERT_EQ(sequenceNetFailure(broken, true), "");
  broken[40].x = broken[41].x;  // two points in one column
  EXPECT_NE(sequenceNetFailure(broken, false), "");
}

TEST(Pmj02, RawSequencesArePrefixAndBlockNets) {
  for (std::uint64_t seed : {1u, 2u, 77u}) {
    const std::vector<Point2> s = pmj02Sequence(seed, 12);
    EXPECT_EQ(sequenceNetFailure(s, true), "") << "seed " << seed;
  }
}

// The sequence of 2^k points of a seed is the prefix of every longer one.
TEST(Pmj02, SequencesAreProgressive) {
  const std::vector<Point2> shorter = pmj02Sequence(9, 6), longer = pmj02Sequence(9, 10);
  for (std::size_t i = 0; i < shorter.size(); ++i) ASSERT_EQ(shorter[i], longer[i]) << i;
  EXPECT_NE(pmj02Sequence(10, 6), shorter);
  EXPECT_EQ(pmj02Sequence(0, 0).size(), 1u);
  EXPECT_THROW(pmj02Sequence(0, kPmj02MaxLog2 + 1), std::invalid_argument);
}

// Owen scrambling and the digital shift map elementary intervals onto
// elementary intervals: every randomized set keeps the base's nets, for any
// N (a non-power of two keeps them in its power-of-two prefixes).
TEST(Pmj02, RandomizedSetsKeepTheirNets) {
  for (const DigitRandomization r :
       {DigitRandomization::Owen, DigitRandomization::Shift, DigitRandomization::None})
    for (std::size_t n : {1u, 2u, 3u, 5u, 12u, 16u, 100u, 256u, 1000u, 4096u})
      for (std::uint64_t seed : {0u, 1u, 1234567u}) {
        std::vector<Point2> pts(n);
        pmj02Set(seed, pts, r);
        ASSERT_EQ(sequenceNetFailure(pts, true), "") << "n " << n << " seed " << seed;
      }
}

TEST(Pmj02, SeedsGiveIndependentSetsButNoneIsFixed) {
  std::vector<Point2> a(64), b(64), c(64);
  pmj02Set(1, a);
  pmj02Set(2, b);
  pmj02Set(1, c);
  EXPECT_EQ(a, c);
  EXPECT_NE(a, b);
  pmj02Set(1, a, DigitRandomization::None);
  pmj02Set(2, b, DigitRandomization::None);
  EXPECT_EQ(a, b);
  pmj02Set(1, a, DigitRandomization::Shift);
  pmj02Set(2, b, DigitRandomization::Shift);
  EXPECT_NE(a, b);
}

// Within its stratum of side 1/N a scrambled point is uniform: the first
// point's position within its 1/16 column, over seeds, by chi-square.
TEST(Pmj02, ScrambledPointsAreUniformWithinTheirStrata) {
  std::vector<int> bins(16), cells(16);
  std::vector<Point2> pts(16);
  for (int s = 0; s < 4000; ++s) {
    pmj02Set(std::uint64_t(s), pts);
    ++bins[int(std::fmod(pts[3].x * 16, 1.0) * 16)];
    ++cells[int(pts[0].y * 16)];
  }
  EXPECT_LT(test::chiSquareUniform(bins), test::chiSquareCritical(16));
  EXPECT_LT(test::chiSquareUniform(cells), test::chiSquareCritical(16));
}

// pmj02Sample is point `index` of the same randomized sequence: for a set
// of N it agrees with pmj02Set in the ceil(log2 N) leading digits (the ones
// the set scrambles one by one) and exactly when unscrambled or shifted.
TEST(Pmj02, SamplesAgreeWithSets) {
  const std::size_t n = 100;
  const int k = 7;
  for (const DigitRandomization r :
       {DigitRandomization::Owen, DigitRandomization::Shift, DigitRandomization::None}) {
    std::vector<Point2> set(n);
    pmj02Set(42, set, r);
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 2; ++c) {
        const double v = pmj02Sample(42, i, c, r), w = set[i][c];
        if (r == DigitRandomization::Owen)
          ASSERT_EQ(std::floor(v * (1 << k)), std::floor(w * (1 << k))) << i << " " << c;
        else
          ASSERT_EQ(v, w) << i << " " << c;
      }
  }
}

TEST(Pmj02, LargestSetIsServedAndLargerAreRefused) {
  std::vector<Point2> pts(kPmj02MaxSet);
  pmj02Set(3, pts);
  EXPECT_EQ(test::netFailure(pts, 16), "");
  std::vector<Point2> tooMany(kPmj02MaxSet + 1);
  try {
    pmj02Set(3, tooMany);
    FAIL();
  } catch (const std::invalid_argument &e) {
    EXPECT_EQ(std::string(e.what()), "pmj02: 65537 points; at most 65536 are served");
  }
  EXPECT_THROW(pmj02Sample(3, kPmj02MaxSet, 0), std::invalid_argument);
}

}  // namespace
}  // namespace nuld
