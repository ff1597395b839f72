// Gaussian blue noise (sampler/bluenoise/gaussian_blue_noise.h): forces
// against finite differences of the energy and against the all-pairs sum,
// uniform sets far more even than their random start, adaptive sets
// following their target (chi-square), stiff targets, and clear errors.

#include "sampler/bluenoise/gaussian_blue_noise.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sampler/metrics/discrepancy.h"
#include "sampler/metrics/nonuniform_l2.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/target_spec.h"
#include "tests/common/chi_square.h"
#include "tests/common/expect_error.h"

namespace nuld {
namespace {

std::vector<Point2> randomPoints(std::size_t n, std::uint64_t seed) {
  Rng rng(seed, 4);
  std::vector<Point2> p(n);
  for (Point2 &q : p) q = {rng.uniform(), rng.uniform()};
  return p;
}

double meanNearestDistance(const std::vector<Point2> &p) {
  double sum = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    double best = 1e9;
    for (std::size_t j = 0; j < p.size(); ++j)
      if (j != i) best = std::min(best, std::hypot(p[i].x - p[j].x, p[i].y - p[j].y));
    sum += best;
  }
  return sum / double(p.size());
}

TEST(GaussianBlueNoise, ForcesAreTheEnergysNegativeGradient) {
  const auto uniform = makeTarget("uniform");
  for (const BlueNoiseBoundary boundary :
       {BlueNoiseBoundary::Bounded, BlueNoiseBoundary::Toroidal}) {
    GaussianBlueNoiseSettings s;
    s.boundary = boundary;
    s.sigma = 1.5;  // wide kernels: every pair and the edges matter
    const std::size_t n = 12;
    const GaussianBlueNoise gbn(*uniform, s, n);
    std::vector<Point2> p = randomPoints(n, 2), f(n);
    gbn.forces(p, f, true);
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 2; ++c) {
        const double h = 1e-6;
        std::vector<Point2> plus = p, minus = p;
        (c == 0 ? plus[i].x : plus[i].y) += h;
        (c == 0 ? minus[i].x : minus[i].y) -= h;
        const double fd = -(gbn.energy(plus) - gbn.energy(minus)) / (2 * h);
        EXPECT_NEAR(c == 0 ? f[i].x : f[i].y, fd, 1e-6 * (1 + std::abs(fd))) << i << " " << c;
      }
  }
}

TEST(GaussianBlueNoise, CutoffGridAgreesWithAllPairs) {
  for (const std::string spec : {"uniform", "gaussian:0.4,0.6,0.2", "step:0.5,1e-6,1"})
    for (const BlueNoiseBoundary boundary :
         {BlueNoiseBoundary::Bounded, BlueNoiseBoundary::Toroidal}) {
      const auto target = makeTarget(spec);
      if (spec != "uniform" && boundary == BlueNoiseBoundary::Toroidal) continue;
      GaussianBlueNoiseSettings s;
      s.boundary = boundary;
      s.targetSamples = 4096;
      const std::size_t n = 300;
      const GaussianBlueNoise gbn(*target, s, n);
      const std::vector<Point2> p = randomPoints(n, 3);
      std::vector<Point2> grid(n), all(n);
      gbn.forces(p, grid);
      gbn.forces(p, all, true);
      double largest = 0;
      for (const Point2 &q : all) largest = std::max(largest, std::hypot(q.x, q.y));
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_LE(std::hypot(grid[i].x - all[i].x, grid[i].y - all[i].y), 1e-5 * largest)
            << spec << " " << i;
    }
}

TEST(GaussianBlueNoise, UniformSetsAreEvenAndLowDiscrepancy) {
  const auto uniform = makeTarget("uniform");
  for (const BlueNoiseBoundary boundary :
       {BlueNoiseBoundary::Bounded, BlueNoiseBoundary::Toroidal}) {
    GaussianBlueNoiseSettings s;
    s.boundary = boundary;
    s.iterations = 300;
    const std::size_t n = 256;
    // Each variant by the discrepancy of its own domain: a toroidal set is
    // even on the torus, where its seam is no edge.
    const bool torus = boundary == BlueNoiseBoundary::Toroidal;
    auto discrepancy = [&](const std::vector<Point2> &q) {
      return torus ? periodicL2(q) : l2StarDiscrepancy(q);
    };
    std::vector<Point2> p = randomPoints(n, 7);
    const double before = discrepancy(p), spacing = meanNearestDistance(p);
    GaussianBlueNoise(*uniform, s, n).optimize(p);
    for (const Point2 &q : p) ASSERT_TRUE(q.x >= 0 && q.x < 1 && q.y >= 0 && q.y < 1);
    EXPECT_LT(discrepancy(p), 0.5 * before) << torus;
    // Blue noise: nearest neighbours near the hexagonal spacing
    // sqrt(2 / (sqrt(3) N)), far from a random set's 0.5 / sqrt(N).
    EXPECT_GT(meanNearestDistance(p), 1.5 * spacing);
  }
}

// A step target (density 0.2 left of x = 0.4, 1 right of it), 4 sets of
// 1024 pooled against the target's mass on an 8 x 8 grid.
TEST(GaussianBlueNoise, AdaptiveSetsFollowTheirTarget) {
  const auto target = makeTarget("step:0.4,0.2,1");
  GaussianBlueNoiseSettings s;
  s.iterations = 100;
  const GaussianBlueNoise gbn(*target, s, 1024);
  std::vector<double> observed(64, 0), expected(64, 0);
  for (std::uint64_t k = 0; k < 4; ++k) {
    std::vector<Point2> p = randomPoints(1024, 40 + k);
    gbn.optimize(p);
    for (const Point2 &q : p) ++observed[std::size_t(q.y * 8) * 8 + std::size_t(q.x * 8)];
  }
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i)
      expected[std::size_t(j * 8 + i)] =
          4 * 1024 * target->mass({{i / 8.0, j / 8.0}, {(i + 1) / 8.0, (j + 1) / 8.0}});
  const test::ChiSquare chi = test::pooledChiSquare(observed, expected);
  EXPECT_GT(chi.pValue, 1e-3) << chi.statistic << " " << chi.note;
}

// A peaked target (a Gaussian of standard deviation 0.15): widths vary by
// 6x over the set, which blew sets up before the trust region; now the
// sets relax from independent target samples to a lower grid L2.
TEST(GaussianBlueNoise, PeakedTargetsRelaxInsteadOfBlowingUp) {
  const auto target = makeTarget("gaussian:0.5,0.5,0.15");
  const NonuniformL2asd l2(*target, 128);
  GaussianBlueNoiseSettings s;
  s.iterations = 300;
  const GaussianBlueNoise gbn(*target, s, 64);
  for (std::uint64_t k = 0; k < 2; ++k) {
    std::vector<Point2> p = randomPoints(64, 60 + k);
    for (Point2 &q : p) q = target->invert(q).x;
    const double before = l2.squared(p);
    gbn.optimize(p);
    EXPECT_LT(l2.squared(p), 0.5 * before) << k;
    for (const Point2 &q : p) EXPECT_LT(std::hypot(q.x - 0.5, q.y - 0.5), 0.6);
  }
}

TEST(GaussianBlueNoise, StiffTargetsGiveFinitePointsInTheDomain) {
  GaussianBlueNoiseSettings s;
  s.iterations = 50;
  s.targetSamples = 2048;
  for (const std::string spec :
       {"uniform", "step:0.5,0,1", "step:0.5,1e-6,1", "gaussian:0.1,0.9,0.01"})
    for (const std::size_t n : {1, 7, 129}) {
      const auto target = makeTarget(spec);
      std::vector<Point2> p = randomPoints(n, 5);
      GaussianBlueNoise(*target, s, n).optimize(p);
      for (const Point2 &q : p)
        ASSERT_TRUE(std::isfinite(q.x) && std::isfinite(q.y) && q.x >= 0 && q.x < 1 && q.y >= 0 &&
                    q.y < 1)
            << spec << " " << n;
    }
}

TEST(GaussianBlueNoise, BadSettingsAreClearErrors) {
  const auto uniform = makeTarget("uniform");
  auto expectError = [&](GaussianBlueNoiseSettings s, const std::string &what) {
    test::expectRefusalMentioning([&] { GaussianBlueNoise(*uniform, s, 4); }, what);
  };
  GaussianBlueNoiseSettings s;
  s.sigma = 0;
  expectError(s, "sigma");
  s = {};
  s.step = -1;
  expectError(s, "step");
  s = {};
  s.boundary = BlueNoiseBoundary::Toroidal;
  EXPECT_THROW(GaussianBlueNoise(*makeTarget("quarterdisc"), s, 4), std::invalid_argument);
  EXPECT_THROW(GaussianBlueNoise(*uniform, GaussianBlueNoiseSettings{}, 0), std::invalid_argument);
}

}  // namespace
}  // namespace nuld
