// What every classic set shares (stratified, pmj02, lattice, zsobol, with
// Owen-Sobol as the control): determinism, [0, 1)^2, any N, distinct seeds,
// unbiased estimates; and the N-based kinds behind sequence.h.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "sampler/sequences/lattice.h"
#include "sampler/sequences/pmj02.h"
#include "sampler/sequences/sequence.h"
#include "sampler/sequences/stratified.h"
#include "sampler/sequences/zsobol.h"
#include "tests/sampler/classic_set_oracles.h"

namespace nuld {
namespace {

struct Maker {
  const char *name;
  test::SetMaker make;
};

std::vector<Maker> makers() {
  return {
      {"owen-sobol",
       [](std::uint64_t s, std::span<Point2> o) {
         generateSet({SequenceKind::Sobol, Scramble::Owen, s}, 0, o);
       }},
      {"stratified", [](std::uint64_t s, std::span<Point2> o) { stratifiedSet(s, o); }},
      {"pmj02", [](std::uint64_t s, std::span<Point2> o) { pmj02Set(s, o); }},
      {"pmj02-shift",
       [](std::uint64_t s, std::span<Point2> o) { pmj02Set(s, o, DigitRandomization::Shift); }},
      {"lattice", [](std::uint64_t s, std::span<Point2> o) { latticeSet(s, o); }},
      {"lattice-baker", [](std::uint64_t s, std::span<Point2> o) { latticeBakerSet(s, o); }},
      {"zsobol", [](std::uint64_t s, std::span<Point2> o) { zsobolSet(s, 3, 5, 2, 8, o); }},
  };
}

TEST(ClassicSets, DeterministicInTheUnitSquareAndSeedsDiffer) {
  for (const Maker &m : makers())
    for (std::size_t n : {1u, 2u, 3u, 5u, 12u, 16u, 100u, 256u}) {
      std::vector<Point2> a(n), b(n), c(n);
      m.make(7, a);
      m.make(7, b);
      m.make(8, c);
      EXPECT_EQ(a, b) << m.name << " n " << n;
      EXPECT_NE(a, c) << m.name << " n " << n;
      for (const Point2 &p : a)
        ASSERT_TRUE(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1) << m.name << " n " << n;
    }
}

// The mean of a smooth integrand's estimate over 3000 seeds is its integral
// within 4 standard errors (and the standard error is not zero: the sets
// are randomized), for powers of two and not.
TEST(ClassicSets, EstimatesAreUnbiased) {
  for (const Maker &m : makers())
    for (std::size_t n : {1u, 5u, 16u}) {
      const test::MeanEstimate e = test::smoothIntegrandMean(m.make, n, 3000);
      EXPECT_GT(e.standardError, 0) << m.name << " n " << n;
      EXPECT_NEAR(e.mean, e.exact, 4 * e.standardError) << m.name << " n " << n;
    }
}

TEST(ClassicSets, KindsParseAndTakeTheirDefaultScrambling) {
  EXPECT_EQ(parseSequenceKind("stratified"), SequenceKind::Stratified);
  EXPECT_EQ(parseSequenceKind("pmj02"), SequenceKind::Pmj02);
  EXPECT_EQ(parseSequenceKind("lattice"), SequenceKind::Lattice);
  EXPECT_EQ(defaultScramble(SequenceKind::Stratified), Scramble::None);
  EXPECT_EQ(defaultScramble(SequenceKind::Pmj02), Scramble::Owen);
  EXPECT_EQ(defaultScramble(SequenceKind::Lattice), Scramble::CranleyPatterson);
  EXPECT_EQ(defaultScramble(SequenceKind::Sobol), Scramble::Owen);
}

std::string refusal(const SequenceOptions &o) {
  try {
    generatePointSet(o, 4, 1);
  } catch (const std::invalid_argument &e) {
    return e.what();
  }
  return "";
}

TEST(ClassicSets, ScramblingsThatDoNotApplyAreRefusedInWords) {
  EXPECT_EQ(refusal({SequenceKind::Stratified, Scramble::Owen, 0}),
            "scrambling 'owen' does not apply to sequence 'stratified': its jitter, one uniform "
            "point per cell, is its randomization (expected none)");
  EXPECT_EQ(refusal({SequenceKind::Lattice, Scramble::Owen, 0}),
            "scrambling 'owen' does not apply to sequence 'lattice' (expected cp or shift, its "
            "random toroidal shift, baker, or none)");
  EXPECT_EQ(refusal({SequenceKind::Sobol, Scramble::Baker, 0}),
            "scrambling 'baker' does not apply to sequence 'sobol': the baker's transform folds "
            "a shifted lattice (expected lattice)");
  EXPECT_EQ(refusal({SequenceKind::Pmj02, Scramble::CranleyPatterson, 0}),
            "scrambling 'cp' does not apply to sequence 'pmj02': a toroidal shift would break "
            "its (0,2) nets (expected owen, shift or none)");
  for (Scramble s : {Scramble::Shift, Scramble::CranleyPatterson, Scramble::Baker, Scramble::None})
    EXPECT_EQ(refusal({SequenceKind::Lattice, s, 0}), "");
  for (Scramble s : {Scramble::Owen, Scramble::Shift, Scramble::None})
    EXPECT_EQ(refusal({SequenceKind::Pmj02, s, 0}), "");
  EXPECT_EQ(refusal({SequenceKind::Stratified, Scramble::None, 0}), "");
}

TEST(ClassicSets, SetsOfNHaveNoPointByIndex) {
  for (SequenceKind k : {SequenceKind::Stratified, SequenceKind::Lattice}) {
    try {
      sequenceSample({k, defaultScramble(k), 0}, 3, 0);
      FAIL();
    } catch (const std::invalid_argument &e) {
      EXPECT_NE(std::string(e.what()).find("is a set of N points, not a sequence"),
                std::string::npos)
          << e.what();
    }
  }
}

// generatePointSet's instances: the kind's own sets, randomized per
// instance, identical when unrandomized.
TEST(ClassicSets, PointSetsThroughTheSequenceInterface) {
  const auto instances = [](SequenceKind k, Scramble s) {
    return generatePointSet({k, s, 5}, 12, 3);
  };
  for (SequenceKind k : {SequenceKind::Stratified, SequenceKind::Pmj02, SequenceKind::Lattice}) {
    const PointSet set = instances(k, defaultScramble(k));
    ASSERT_EQ(set.points.size(), 36u);
    EXPECT_TRUE(randomizesInstances({k, defaultScramble(k), 5}));
    EXPECT_NE(set.points[0], set.points[12]) << toString(k);
    EXPECT_EQ(set.metadata.at("generator"), std::string(toString(k)));
  }
  for (SequenceKind k : {SequenceKind::Pmj02, SequenceKind::Lattice}) {
    const PointSet set = instances(k, Scramble::None);
    EXPECT_FALSE(randomizesInstances({k, Scramble::None, 5}));
    for (std::size_t i = 0; i < 12; ++i) EXPECT_EQ(set.points[i], set.points[12 + i]);
  }
  std::vector<Point2> lattice(12);
  rank1Lattice(lattice);
  const PointSet raw = instances(SequenceKind::Lattice, Scramble::None);
  for (std::size_t i = 0; i < 12; ++i) EXPECT_EQ(raw.points[i], lattice[i]);
}

// pmj02 is a sequence: generatePoints is sequenceSample point by point
// (dimension d is coordinate d % 2 of pair d / 2), and generateSet is
// pmj02Set of the pair's seed.
TEST(ClassicSets, Pmj02PointsSamplesAndSetsAgree) {
  const SequenceOptions o{SequenceKind::Pmj02, Scramble::Owen, 21};
  std::vector<Point2> points(20), set(20), direct(20);
  generatePoints(o, 2, points, 4);
  generateSet(o, 2, set, 4);
  pmj02Set(dimensionSeed(21, 2, 4), direct);
  for (std::size_t i = 0; i < 20; ++i) {
    EXPECT_EQ(points[i].x, sequenceSample(o, i, 4, 2));
    EXPECT_EQ(points[i].y, sequenceSample(o, i, 5, 2));
    EXPECT_EQ(set[i], direct[i]);
    EXPECT_EQ(std::floor(points[i].x * 32), std::floor(set[i].x * 32));
  }
  EXPECT_THROW(generatePointSet(o, kPmj02MaxSet + 1, 1), std::invalid_argument);
}

}  // namespace
}  // namespace nuld
