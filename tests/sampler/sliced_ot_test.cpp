// Sliced optimal transport sampling (sampler/bluenoise/sliced_ot.h): the
// uniform square's and disc's projection slab means against brute force,
// the concentric map, uniform sets
// far below random ones in discrepancy, non-uniform sets following their
// target (chi-square), stiff targets, and clear errors.

#include "sampler/bluenoise/sliced_ot.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sampler/metrics/discrepancy.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/target_spec.h"
#include "tests/common/chi_square.h"
#include "tests/common/expect_error.h"

namespace nuld {
namespace {

std::vector<Point2> randomPoints(std::size_t n, std::uint64_t seed) {
  Rng rng(seed, 3);
  std::vector<Point2> p(n);
  for (Point2 &q : p) q = {rng.uniform(), rng.uniform()};
  return p;
}

TEST(SlicedOt, UniformProjectionSlabMeansEqualBruteForce) {
  const std::vector<Point2> many = randomPoints(700000, 1);
  for (const double angle : {0.0, 0.3, 1.1, 2.0, 3.9, 5.5}) {
    const Point2 theta{std::cos(angle), std::sin(angle)};
    std::vector<double> proj;
    for (const Point2 &p : many) proj.push_back(p.x * theta.x + p.y * theta.y);
    std::sort(proj.begin(), proj.end());
    std::vector<double> got(7);
    uniformProjectionSlabMeans(theta, got);
    for (std::size_t k = 0; k < got.size(); ++k) {
      double mean = 0;
      const std::size_t block = proj.size() / 7;
      for (std::size_t j = k * block; j < (k + 1) * block; ++j) mean += proj[j] / double(block);
      EXPECT_NEAR(got[k], mean, 2e-3) << angle << " " << k;
    }
    // The slabs' means average to the projection's mean.
    double sum = 0;
    for (const double v : got) sum += v / 7;
    EXPECT_NEAR(sum, 0.5 * (theta.x + theta.y), 1e-12) << angle;
  }
  // Along an axis the projection is uniform: slab k's mean is (k + 1/2)/N.
  std::vector<double> q(4);
  uniformProjectionSlabMeans({-1, 0}, q);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(q[k], -1 + (double(k) + 0.5) / 4, 1e-15);
}

// The inscribed disc's projection is the same along every direction: its
// slabs' means against sorting a dense disc sample, symmetric about 0.
TEST(SlicedOt, UniformDiscSlabMeansEqualBruteForce) {
  std::vector<double> proj;
  for (const Point2 &p : randomPoints(900000, 2)) {
    const Point2 d{p.x - 0.5, p.y - 0.5};
    if (d.x * d.x + d.y * d.y < 0.25) proj.push_back(0.6 * d.x + 0.8 * d.y);
  }
  std::sort(proj.begin(), proj.end());
  std::vector<double> got(9);
  uniformDiscSlabMeans(got);
  const std::size_t block = proj.size() / 9;
  for (std::size_t k = 0; k < 9; ++k) {
    double mean = 0;
    for (std::size_t j = k * block; j < (k + 1) * block; ++j) mean += proj[j] / double(block);
    EXPECT_NEAR(got[k], mean, 1e-3) << k;
    EXPECT_NEAR(got[k], -got[8 - k], 1e-12) << k;
  }
  std::vector<double> one(1);
  uniformDiscSlabMeans(one);
  EXPECT_NEAR(one[0], 0, 1e-15);
}

// The concentric map and its inverse: a round trip returns the point (wedge
// seams and the centre included), and it preserves area.
TEST(SlicedOt, ConcentricMapIsAnAreaPreservingBijection) {
  std::vector<Point2> points = randomPoints(2000, 4);
  for (const double t : {0.0, 0.1, 0.25, 0.5, 0.75, 0.9})
    points.insert(points.end(), {{t, t}, {t, 1 - t}, {0.5, t}, {t, 0.5}});
  for (const Point2 &u : points) {
    const Point2 p = squareToDisc(u);
    ASSERT_LE(std::hypot(p.x - 0.5, p.y - 0.5), 0.5 + 1e-15) << u.x << " " << u.y;
    const Point2 back = discToSquare(p);
    EXPECT_NEAR(back.x, u.x, 1e-12) << u.x << " " << u.y;
    EXPECT_NEAR(back.y, u.y, 1e-12) << u.x << " " << u.y;
  }
  // Equal area: the Jacobian determinant is the disc's area, pi / 4,
  // everywhere (central differences, away from the wedges' seams).
  for (const Point2 &u : randomPoints(300, 5)) {
    const double h = 1e-6;
    const Point2 dx = squareToDisc({u.x + h, u.y}) - squareToDisc({u.x - h, u.y});
    const Point2 dy = squareToDisc({u.x, u.y + h}) - squareToDisc({u.x, u.y - h});
    const double det = (dx.x * dy.y - dx.y * dy.x) / (4 * h * h);
    if (std::abs(std::abs(u.x - 0.5) - std::abs(u.y - 0.5)) > 1e-4) {
      EXPECT_NEAR(det, std::numbers::pi / 4, 1e-6) << u.x << " " << u.y;
    }
  }
}

// The disc is the default for uniform sets because it measures better than
// the square (module comment); the same starts and directions here.
TEST(SlicedOt, UniformSetsInTheDiscBeatTheSquare) {
  const auto uniform = makeTarget("uniform");
  SlicedOtSettings disc, square;
  disc.iterations = square.iterations = 256;
  disc.slices = square.slices = 32;
  square.uniformDomain = UniformSotDomain::Square;
  double l2Disc = 0, l2Square = 0;
  for (std::uint32_t set = 0; set < 2; ++set) {
    std::vector<Point2> a = randomPoints(200, 30 + set), b = a;
    slicedOtTransport(SliceDestinations(*uniform, disc, 200), disc, set, a);
    slicedOtTransport(SliceDestinations(*uniform, square, 200), square, set, b);
    for (const Point2 &q : a) ASSERT_TRUE(q.x >= 0 && q.x < 1 && q.y >= 0 && q.y < 1);
    l2Disc += l2StarDiscrepancy(a);
    l2Square += l2StarDiscrepancy(b);
  }
  EXPECT_LT(l2Disc, 0.85 * l2Square);
  EXPECT_EQ(parseUniformSotDomain(toString(UniformSotDomain::Square)), UniformSotDomain::Square);
  EXPECT_THROW(parseUniformSotDomain("ball"), std::invalid_argument);
}

TEST(SlicedOt, UniformSetsHaveFarLowerDiscrepancyThanTheirRandomStart) {
  const auto uniform = makeTarget("uniform");
  SlicedOtSettings s;
  s.iterations = 256;
  s.slices = 32;
  for (const std::size_t n : {1, 3, 100, 256}) {
    std::vector<Point2> p = randomPoints(n, n);
    const double before = l2StarDiscrepancy(p);
    slicedOtTransport(SliceDestinations(*uniform, s, n), s, 0, p);
    for (const Point2 &q : p) ASSERT_TRUE(q.x >= 0 && q.x < 1 && q.y >= 0 && q.y < 1) << n;
    if (n >= 100) {
      EXPECT_LT(l2StarDiscrepancy(p), 0.4 * before) << n;
    }
    if (n == 1) {
      EXPECT_NEAR(p[0].x, 0.5, 1e-9);  // the median of every projection
    }
  }
}

// A step target (density 0.2 left of x = 0.4, 1 right of it): 4 sets of
// 1024 points, pooled, against the target's mass on an 8 x 8 grid. (With
// few points per set a sparse region holds a handful of evenly spaced
// points, whose spacing beats against the bins; 1024 keep it finer.)
TEST(SlicedOt, NonUniformSetsFollowTheirTarget) {
  const auto target = makeTarget("step:0.4,0.2,1");
  SlicedOtSettings s;
  s.iterations = 200;
  s.slices = 32;
  s.targetSamples = 16384;
  const SliceDestinations destinations(*target, s, 1024);
  std::vector<double> observed(64, 0), expected(64, 0);
  for (std::uint32_t k = 0; k < 4; ++k) {
    std::vector<Point2> p = randomPoints(1024, 100 + k);
    slicedOtTransport(destinations, s, k, p);
    for (const Point2 &q : p) ++observed[std::size_t(q.y * 8) * 8 + std::size_t(q.x * 8)];
  }
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i)
      expected[std::size_t(j * 8 + i)] =
          4 * 1024 * target->mass({{i / 8.0, j / 8.0}, {(i + 1) / 8.0, (j + 1) / 8.0}});
  const test::ChiSquare chi = test::pooledChiSquare(observed, expected);
  EXPECT_GT(chi.pValue, 1e-3) << chi.statistic << " " << chi.note;
  // The left columns hold a fifth of the right's density.
  double left = 0, right = 0;
  for (int j = 0; j < 8; ++j)
    left += observed[std::size_t(j * 8)], right += observed[std::size_t(j * 8 + 7)];
  EXPECT_NEAR(left / right, 0.2, 0.05);
}

TEST(SlicedOt, StiffTargetsGiveFinitePointsInTheDomain) {
  SlicedOtSettings s;
  s.iterations = 64;
  s.slices = 16;
  s.targetSamples = 2048;
  for (const std::string spec : {"step:0.5,0,1", "step:0.5,1e-6,1", "gaussian:0.1,0.9,0.01"}) {
    const auto target = makeTarget(spec);
    for (const std::size_t n : {1, 7, 129}) {
      std::vector<Point2> p = randomPoints(n, 5);
      slicedOtTransport(SliceDestinations(*target, s, n), s, 0, p);
      for (const Point2 &q : p)
        ASSERT_TRUE(std::isfinite(q.x) && std::isfinite(q.y) && q.x >= 0 && q.x < 1 && q.y >= 0 &&
                    q.y < 1)
            << spec << " " << n;
    }
  }
  // With no mass left of x = 1/2, the points leave that half.
  std::vector<Point2> p = randomPoints(256, 9);
  s.iterations = 256;
  slicedOtTransport(SliceDestinations(*makeTarget("step:0.5,0,1"), s, 256), s, 0, p);
  const auto left = std::count_if(p.begin(), p.end(), [](Point2 q) { return q.x < 0.49; });
  EXPECT_LE(left, 2);
}

TEST(SlicedOt, BadSettingsAreClearErrors) {
  const auto uniform = makeTarget("uniform");
  std::vector<Point2> p = randomPoints(4, 1);
  auto expectError = [&](SlicedOtSettings s, const std::string &what) {
    test::expectRefusalMentioning(
        [&] { slicedOtTransport(SliceDestinations(*uniform, s, 4), s, 0, p); }, what);
  };
  SlicedOtSettings s;
  s.slices = 0;
  expectError(s, "slices");
  s = {};
  s.step = std::nan("");
  expectError(s, "step");
  s = {};
  s.iterations = -1;
  expectError(s, "iterations");
  EXPECT_THROW(SliceDestinations(*uniform, SlicedOtSettings{}, 0), std::invalid_argument);
  EXPECT_THROW(slicedOtTransport(SliceDestinations(*uniform, SlicedOtSettings{}, 5), {}, 0, p),
               std::invalid_argument);  // built for 5 points, given 4
}

// The tabulated destinations of a non-uniform target, at directions off the
// table and across the half-turn seam, against sorting the same sample.
TEST(SlicedOt, TabulatedDestinationsMatchSortingTheSample) {
  const auto target = makeTarget("gaussian:0.3,0.6,0.2");
  SlicedOtSettings s;
  s.targetSamples = 8192;
  const std::size_t n = 16;
  const SliceDestinations destinations(*target, s, n);
  std::vector<Point2> sample(s.targetSamples);
  generateSet({SequenceKind::Sobol, Scramble::Owen, hash3(s.seed, 0x50715A, n)}, 0, sample);
  for (Point2 &p : sample) p = target->invert(p).x;
  for (const double angle : {0.001, 0.7, 1.5707, 3.14159, -0.4, -3.1415}) {
    const Point2 theta{std::cos(angle), std::sin(angle)};
    std::vector<double> proj;
    for (const Point2 &p : sample) proj.push_back(p.x * theta.x + p.y * theta.y);
    std::sort(proj.begin(), proj.end());
    std::vector<double> got(n);
    destinations.along(theta, got);
    for (std::size_t k = 0; k < n; ++k) {
      double mean = 0;
      for (std::size_t j = k * 512; j < (k + 1) * 512; ++j) mean += proj[j] / 512;
      EXPECT_NEAR(got[k], mean, 2e-4) << angle << " " << k;  // the table's angular step
    }
  }
}

}  // namespace
}  // namespace nuld
