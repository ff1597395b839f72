// Sequences: published values, index conventions, randomization invariants.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <span>
#include <stdexcept>
#include <vector>

#include "sampler/sequences/rng.h"
#include "sampler/sequences/scrambling.h"
#include "sampler/sequences/sequence.h"
#include "sampler/sequences/sobol.h"

namespace nuld {
namespace {

// Joe & Kuo's reference program (and e.g. Apache Commons Math's tests), index 0 included.
TEST(Sobol, FirstPointsMatchPublishedValues) {
  const double expected[10][3] = {{0, 0, 0},
                                  {0.5, 0.5, 0.5},
                                  {0.75, 0.25, 0.25},
                                  {0.25, 0.75, 0.75},
                                  {0.375, 0.375, 0.625},
                                  {0.875, 0.875, 0.125},
                                  {0.625, 0.125, 0.875},
                                  {0.125, 0.625, 0.375},
                                  {0.1875, 0.3125, 0.9375},
                                  {0.6875, 0.8125, 0.4375}};
  for (int i = 0; i < 10; ++i)
    for (int d = 0; d < 3; ++d) EXPECT_EQ(sobolSample(i, d), expected[i][d]) << i << "," << d;
}

TEST(Sobol, EveryDimensionIsANetInOneDimension) {
  // Any 2^m consecutive-from-zero points hit each interval [k/2^m, (k+1)/2^m) once.
  for (std::uint32_t d = 0; d < kSobolMaxDimensions; ++d) {
    std::set<std::uint32_t> cells;
    for (int i = 0; i < 1024; ++i) cells.insert(sobolBits(i, d) >> 22);
    EXPECT_EQ(cells.size(), 1024u) << "dimension " << d;
  }
}

// The Gray-code recurrence must give every point exactly as the direct
// formula, in every dimension, for runs of any length (N = 1, not powers of 2).
TEST(Sobol, RunsEqualPointwiseValues) {
  for (std::uint32_t dim = 0; dim < kSobolMaxDimensions; ++dim)
    for (std::size_t n : {1u, 2u, 3u, 7u, 64u, 1000u}) {
      std::vector<std::uint32_t> run(n);
      sobolRun(dim, run);
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_EQ(run[i], sobolBits(i, dim)) << "dim " << dim << " n " << n << " i " << i;
    }
  std::vector<std::uint32_t> empty;
  sobolRun(0, empty);
  std::vector<std::uint32_t> one(1);
  EXPECT_THROW(sobolRun(kSobolMaxDimensions, one), std::out_of_range);
}

TEST(Sobol, RejectsOutOfRangeDimension) {
  EXPECT_THROW(sobolBits(0, kSobolMaxDimensions), std::out_of_range);
}

TEST(Halton, RadicalInverseValues) {
  EXPECT_EQ(radicalInverse(0, 2, DigitRandomization::None, 0), 0.0);
  EXPECT_EQ(radicalInverse(1, 2, DigitRandomization::None, 0), 0.5);
  EXPECT_EQ(radicalInverse(6, 2, DigitRandomization::None, 0), 0.375);  // 110b -> .011b
  EXPECT_NEAR(radicalInverse(5, 3, DigitRandomization::None, 0), 7.0 / 9.0, 1e-15);  // 12_3
  EXPECT_EQ(nthPrime(0), 2u);
  EXPECT_EQ(nthPrime(7), 19u);
  SequenceOptions o{SequenceKind::Halton, Scramble::None, 0};
  EXPECT_NEAR(sequenceSample(o, 4, 1), 4.0 / 9.0, 1e-15);  // 11_3 -> .11_3
}

// Owen scrambling in any base keeps the stratification: the first b^m points
// of a randomized radical inverse hit each interval of width b^-m once.
// Owen-scrambled Halton permutes each digit by the permutation shuffle()
// makes from the prefix's key; permuteDigit finds one digit's image without
// making it, and must give the same permutation: every digit of bases up to
// the largest allowed, over many keys. A base beyond it is refused.
TEST(Halton, PermuteDigitIsTheShufflesPermutation) {
  Rng keys(17);
  for (const std::uint32_t base : {2u, 3u, 5u, 7u, 13u, 97u, 211u, 1024u})
    for (int k = 0; k < 20; ++k) {
      const std::uint64_t key = keys.nextBits();
      std::vector<std::uint32_t> perm(base);
      std::iota(perm.begin(), perm.end(), 0u);
      Rng rng(key);
      shuffle(std::span(perm), rng);
      for (std::uint32_t d = 0; d < base; ++d)
        ASSERT_EQ(permuteDigit(d, base, key), perm[d]) << "base " << base << " digit " << d;
    }
  EXPECT_THROW(permuteDigit(0, 1025, 1), std::invalid_argument);
}

TEST(Halton, ScrambledDigitsKeepStratification) {
  for (auto r : {DigitRandomization::Owen, DigitRandomization::Shift})
    for (std::uint32_t base : {2u, 3u, 5u}) {
      const int n = base == 2 ? 256 : base == 3 ? 243 : 125;
      std::set<int> cells;
      for (int i = 0; i < n; ++i) {
        const double x = radicalInverse(i, base, r, 1234 + base);
        ASSERT_GE(x, 0.0);
        ASSERT_LT(x, 1.0);
        cells.insert(int(x * n));
      }
      EXPECT_EQ(int(cells.size()), n) << "base " << base;
    }
}

TEST(Scrambling, OwenPreservesElementaryIntervalsAndIsNotIdentity) {
  int changed = 0;
  for (std::uint32_t v = 0; v < 4096; ++v) {
    const std::uint32_t s = owenScramble(v << 20, 99);
    changed += (s >> 20) != v;
    // Same prefix in, same prefix out: the scramble is nested.
    EXPECT_EQ(owenScramble(v << 20, 99) >> 20, owenScramble((v << 20) | 0xfffffu, 99) >> 20);
  }
  EXPECT_GT(changed, 3000);
}

TEST(Scrambling, OwenIsUniformAcrossSeeds) {
  // The scrambled image of a fixed point is uniform over seeds: check the
  // first two digits' frequencies.
  int counts[4] = {};
  const int trials = 40000;
  for (int s = 0; s < trials; ++s) ++counts[owenScramble(0x12345678u, s) >> 30];
  for (int c : counts) EXPECT_NEAR(c, trials / 4.0, 5 * std::sqrt(trials * 0.1875));
}

TEST(Sequences, AllOutputsInUnitSquareAndDeterministic) {
  for (auto kind : {SequenceKind::Sobol, SequenceKind::Halton, SequenceKind::Random})
    for (auto scr : {Scramble::None, Scramble::Owen, Scramble::Shift, Scramble::CranleyPatterson}) {
      SequenceOptions o{kind, scr, 42};
      const PointSet a = generatePointSet(o, 1000, 3), b = generatePointSet(o, 1000, 3);
      ASSERT_EQ(a.points.size(), 3000u);
      for (std::size_t i = 0; i < a.points.size(); ++i) {
        ASSERT_GE(a.points[i].x, 0.0);
        ASSERT_LT(a.points[i].x, 1.0);
        ASSERT_GE(a.points[i].y, 0.0);
        ASSERT_LT(a.points[i].y, 1.0);
        ASSERT_EQ(a.points[i], b.points[i]);
      }
      if (scr != Scramble::None || kind == SequenceKind::Random) {
        EXPECT_NE(a.instance(0)[5], a.instance(1)[5]) << "instances must differ";
      }
    }
}

TEST(Sequences, NonPowerOfTwoAndSinglePoint) {
  SequenceOptions o{SequenceKind::Sobol, Scramble::Owen, 7};
  const PointSet one = generatePointSet(o, 1, 4);
  EXPECT_EQ(one.instances(), 4u);
  const PointSet odd = generatePointSet(o, 1000, 1);
  // The 1000 points are a prefix of the 1024-point net.
  const PointSet net = generatePointSet(o, 1024, 1);
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(odd.points[i], net.points[i]);
}

TEST(Rng, UniformMomentsAndIndependentStreams) {
  Rng a(1, 0), b(1, 1);
  double sum = 0, sum2 = 0, cross = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const double x = a.uniform(), y = b.uniform();
    sum += x;
    sum2 += x * x;
    cross += (x - 0.5) * (y - 0.5);
  }
  EXPECT_NEAR(sum / n, 0.5, 5 * std::sqrt(1.0 / 12 / n));
  EXPECT_NEAR(sum2 / n, 1.0 / 3, 0.005);
  EXPECT_NEAR(cross / n, 0.0, 5 * (1.0 / 12) / std::sqrt(double(n)));
}

TEST(Sequences, ParsingErrorsNameTheValue) {
  try {
    parseSequenceKind("sobel");
    FAIL();
  } catch (const std::invalid_argument &e) {
    EXPECT_EQ(std::string(e.what()),
              "unknown sequence 'sobel' (did you mean 'sobol'?) (expected sobol, halton, random, "
              "stratified, pmj02 or lattice)");
  }
  EXPECT_THROW(parseScramble("xor"), std::invalid_argument);
}

}  // namespace
}  // namespace nuld

namespace nuld {
namespace {

// generateSet draws the digits below a point's unique prefix with one hash:
// the set must keep its nets and stratification, and within its stratum each
// point must stay uniform (the digits it draws are not constant or biased).
// Owen-scrambled Sobol sets are built from a table of shared prefixes; every
// point must still be exactly what owenScramble gives it on its own, with
// the set's seed per (instance, dimension) and its distinct-digit count.
TEST(GenerateSet, OwenSobolSetsEqualPointwiseScrambling) {
  for (std::size_t n : {1, 2, 3, 4, 5, 7, 16, 33, 64, 100, 256}) {
    for (std::uint32_t instance : {0u, 3u}) {
      for (std::uint32_t firstDim : {0u, 5u}) {
        const SequenceOptions o{SequenceKind::Sobol, Scramble::Owen, 12345};
        std::vector<Point2> set(n);
        generateSet(o, instance, set, firstDim);
        int d = 0;
        while ((std::size_t(1) << d) < n) ++d;
        for (std::size_t i = 0; i < n; ++i) {
          const auto expected = [&](std::uint32_t dim) {
            return owenScramble(sobolBits(i, dim), dimensionSeed(o.seed, instance, dim), d) *
                   0x1.0p-32;
          };
          ASSERT_EQ(set[i].x, expected(firstDim)) << "n " << n << " point " << i;
          ASSERT_EQ(set[i].y, expected(firstDim + 1)) << "n " << n << " point " << i;
        }
      }
    }
  }
}

TEST(GenerateSet, KeepsNetsAndStratificationForAnyN) {
  for (std::size_t n : {1u, 5u, 64u, 243u, 256u}) {
    for (SequenceKind kind : {SequenceKind::Sobol, SequenceKind::Halton}) {
      std::vector<Point2> pts(n);
      generateSet({kind, Scramble::Owen, 17}, 3, pts);
      std::set<int> xs, ys;
      for (const Point2 &p : pts) {
        ASSERT_TRUE(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1);
        xs.insert(int(p.x * n));
      }
      // Dimension 0 (base 2 for both) is stratified for power-of-two n; for
      // Halton's base-3 dimension 1, n = 243 = 3^5 is stratified too.
      if ((n & (n - 1)) == 0) {
        EXPECT_EQ(xs.size(), n) << toString(kind) << " n " << n;
      }
      if (kind == SequenceKind::Halton && n == 243) {
        for (const Point2 &p : pts) ys.insert(int(p.y * n));
        EXPECT_EQ(ys.size(), n);
      }
    }
  }
}

TEST(GenerateSet, PositionWithinTheStratumIsUniform) {
  for (SequenceKind kind : {SequenceKind::Sobol, SequenceKind::Halton}) {
    double sum = 0, sumSq = 0;
    const int seeds = 4000;
    for (int s = 0; s < seeds; ++s) {
      std::vector<Point2> pts(16);
      generateSet({kind, Scramble::Owen, std::uint64_t(s)}, 0, pts);
      const double f = pts[5].x * 16 - std::floor(pts[5].x * 16);
      sum += f;
      sumSq += f * f;
    }
    const double mean = sum / seeds, var = sumSq / seeds - mean * mean;
    EXPECT_NEAR(mean, 0.5, 4 * std::sqrt(1.0 / 12 / seeds)) << toString(kind);
    EXPECT_NEAR(var, 1.0 / 12, 0.01) << toString(kind);
  }
}

}  // namespace
}  // namespace nuld
