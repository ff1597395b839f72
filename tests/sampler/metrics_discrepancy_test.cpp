// Metrics: the L2-star, L2asd and star discrepancies against exact brute
// force, and the net property of Sobol points.
//
// The brute-force references share no code with the library: the L2
// discrepancies are integrated exactly cell by cell (metric_oracles.h), D* is
// a direct O(N^3) search over the critical boxes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "sampler/metrics/discrepancy.h"
#include "sampler/point.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/target.h"
#include "tests/sampler/metric_oracles.h"

namespace nuld {
namespace {

using test::cornerBox;
using test::exactL2asd;
using test::exactL2Star;
using test::latticePoints;
using test::mapped;
using test::randomPoints;
using test::sequencePoints;
using test::TestRng;

// ------------------------------------------------------------------ helpers

// D* by direct search: every a in {0, x_i, 1}, b in {0, y_i, 1}, closed and
// open anchored boxes, counts by direct comparison. O(N^3).
double bruteStar(std::span<const Point2> p, const std::function<double(double, double)> &mu) {
  std::vector<double> as{0.0, 1.0}, bs{0.0, 1.0};
  for (const Point2 &q : p) {
    as.push_back(q.x);
    bs.push_back(q.y);
  }
  const double N = double(p.size());
  double d = 0;
  for (double a : as)
    for (double b : bs) {
      int closed = 0, open = 0;
      for (const Point2 &q : p) {
        closed += q.x <= a && q.y <= b;
        open += q.x < a && q.y < b;
      }
      const double m = mu(a, b);
      d = std::max({d, std::abs(closed / N - m), std::abs(open / N - m)});
    }
  return d;
}

double uniformAnchored(double a, double b) { return a * b; }

std::function<double(double, double)> targetAnchored(const Target &t) {
  return [&t](double a, double b) { return t.mass({{0, 0}, {a, b}}); };
}

// ------------------------------------------------------- 1. Warnock L2-star

TEST(MetricL2Star, SinglePointClosedForms) {
  // One point at the origin: the count is 1 everywhere, so
  // L2*^2 = int (1 - ab)^2 = 1 - 1/2 + 1/9 = 11/18.
  const Point2 origin[1] = {{0, 0}};
  EXPECT_NEAR(l2StarDiscrepancy(origin), std::sqrt(11.0 / 18.0), 1e-14);
  // One point (x, y): int_{a>=x, b>=y} (1 - ab)^2 + int_rest (ab)^2
  //   = 1/9 - (1 - x^2)(1 - y^2)/2 + (1 - x)(1 - y).
  TestRng rng(1);
  for (int t = 0; t < 50; ++t) {
    const Point2 q[1] = {{rng.uniform(), rng.uniform()}};
    const double x = q[0].x, y = q[0].y;
    const double expected = 1.0 / 9 - (1 - x * x) * (1 - y * y) / 2 + (1 - x) * (1 - y);
    EXPECT_NEAR(l2StarDiscrepancy(q), std::sqrt(expected), 1e-13) << x << "," << y;
    EXPECT_NEAR(l2StarDiscrepancy(q), exactL2Star(q), 1e-13);
  }
  // A point at (1, 1) is only in the box [0,1]^2: L2*^2 = int (ab)^2 = 1/9.
  const Point2 corner[1] = {{1, 1}};
  EXPECT_NEAR(l2StarDiscrepancy(corner), 1.0 / 3, 1e-14);
}

TEST(MetricL2Star, MatchesExactCellIntegration) {
  for (std::size_t n : {1u, 2u, 7u, 16u, 33u})
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      const std::vector<Point2> rnd = randomPoints(n, 100 * n + seed);
      EXPECT_NEAR(l2StarDiscrepancy(rnd), exactL2Star(rnd), 1e-12) << "random N=" << n;
      const std::vector<Point2> owen = sequencePoints(Scramble::Owen, seed, n);
      EXPECT_NEAR(l2StarDiscrepancy(owen), exactL2Star(owen), 1e-12) << "owen N=" << n;
    }
  for (std::size_t n : {1u, 2u, 7u, 16u, 33u}) {
    const std::vector<Point2> sobol = sequencePoints(Scramble::None, 0, n);
    EXPECT_NEAR(l2StarDiscrepancy(sobol), exactL2Star(sobol), 1e-12) << "sobol N=" << n;
    const std::vector<Point2> ties = latticePoints(n, n);
    EXPECT_NEAR(l2StarDiscrepancy(ties), exactL2Star(ties), 1e-12) << "lattice N=" << n;
  }
}

// ---------------------------------------------------------------- 2. L2asd

TEST(MetricL2asd, SinglePointAtOrigin) {
  // Corner (0,0): int (1 - ab)^2 = 11/18; the three other corners never
  // contain the origin (up to measure zero): int (ab)^2 = 1/9 each.
  const Point2 origin[1] = {{0, 0}};
  const double expected = (11.0 / 18 + 3.0 / 9) / 4;  // = 17/72
  EXPECT_NEAR(l2asd(origin), std::sqrt(expected), 1e-14);
}

TEST(MetricL2asd, MatchesExactCellIntegration) {
  for (std::size_t n : {1u, 2u, 7u, 16u, 33u})
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      const std::vector<Point2> rnd = randomPoints(n, 200 * n + seed);
      EXPECT_NEAR(l2asd(rnd), exactL2asd(rnd), 1e-12) << "random N=" << n;
      const std::vector<Point2> owen = sequencePoints(Scramble::Owen, seed + 10, n);
      EXPECT_NEAR(l2asd(owen), exactL2asd(owen), 1e-12) << "owen N=" << n;
    }
  for (std::size_t n : {1u, 2u, 7u, 16u, 33u}) {
    const std::vector<Point2> ties = latticePoints(n, 50 + n);
    EXPECT_NEAR(l2asd(ties), exactL2asd(ties), 1e-12) << "lattice N=" << n;
  }
}

TEST(MetricL2asd, MatchesMonteCarloOverCornerBoxes) {
  // Average of (count/N - vol)^2 over a uniformly random corner and a
  // uniformly random opposite vertex; the estimate must lie within 4
  // standard errors (estimated from the same samples) of l2asd^2.
  for (std::uint64_t seed : {5u, 6u}) {
    const std::vector<Point2> p = randomPoints(24, seed);
    const double N = double(p.size());
    TestRng rng(seed * 7919);
    const int M = 200000;
    double sum = 0, sum2 = 0;
    for (int s = 0; s < M; ++s) {
      const int corner = rng.uniformInt(4);
      const Box2 box = cornerBox(corner & 1, corner >> 1, rng.uniform(), rng.uniform());
      int count = 0;
      for (const Point2 &q : p) count += box.contains(q);
      const double d = count / N - box.area();
      sum += d * d;
      sum2 += d * d * d * d;
    }
    const double mean = sum / M, se = std::sqrt((sum2 / M - mean * mean) / M);
    const double d2 = l2asd(p) * l2asd(p);
    EXPECT_NEAR(mean, d2, 4 * se) << "seed " << seed << " mean " << mean << " se " << se;
    // The Monte Carlo check is only meaningful if it is sharper than the value.
    EXPECT_LT(4 * se, 0.05 * d2);
  }
}

// ------------------------------------------------------------- 3. exact D*

TEST(MetricStarDiscrepancy, SinglePointClosedForm) {
  // One point (x, y): the closed box [0,x]x[0,y] gives 1 - xy, the open boxes
  // [0,x)x[0,1) and [0,1)x[0,y) give x and y; nothing else does better.
  const Point2 cases[] = {{0, 0}, {1, 1}, {1, 0}, {0, 1}, {0.3, 0.7}, {0.5, 0.5}, {0.9, 0.95}};
  for (const Point2 &c : cases) {
    const Point2 p[1] = {c};
    const double expected = std::max({1 - c.x * c.y, c.x, c.y});
    EXPECT_NEAR(starDiscrepancy(p), expected, 1e-15) << c.x << "," << c.y;
    EXPECT_NEAR(bruteStar(p, uniformAnchored), expected, 1e-15);
  }
}

TEST(MetricStarDiscrepancy, UniformMatchesBruteForce) {
  std::vector<std::vector<Point2>> sets;
  for (std::size_t n : {1u, 2u, 3u, 5u, 13u, 31u, 64u}) {
    sets.push_back(randomPoints(n, 300 + n));
    sets.push_back(latticePoints(n, 400 + n));  // ties, 0 and 1.0
    sets.push_back(sequencePoints(Scramble::Owen, n, n));
  }
  // Ties in one coordinate only, and points on the top and right edges.
  std::vector<Point2> tiesX = randomPoints(20, 9), tiesY = randomPoints(21, 10);
  for (std::size_t i = 0; i < tiesX.size(); ++i) tiesX[i].x = (i % 4) / 4.0;
  for (std::size_t i = 0; i < tiesY.size(); ++i) tiesY[i].y = i % 3 == 0 ? 1.0 : 0.25 * (i % 3);
  sets.push_back(tiesX);
  sets.push_back(tiesY);
  sets.push_back({{0, 0}, {0, 0}, {1, 1}, {1, 0}, {0, 1}, {0.5, 1}, {1, 0.5}});
  for (const auto &p : sets) {
    const double brute = bruteStar(p, uniformAnchored);
    EXPECT_NEAR(starDiscrepancy(p), brute, 1e-14) << "N=" << p.size();
    // An explicit uniform target must give the same value.
    const UniformTarget uniform;
    EXPECT_NEAR(starDiscrepancy(p, &uniform), brute, 1e-14) << "N=" << p.size();
  }
}

TEST(MetricStarDiscrepancy, NonUniformMatchesBruteForce) {
  const QuarterDiscTarget disc;
  const BilinearTarget bilinear(1, 2, 0.5, 3);
  for (const Target *t :
       {static_cast<const Target *>(&disc), static_cast<const Target *>(&bilinear)}) {
    for (std::size_t n : {1u, 2u, 7u, 16u, 33u, 64u}) {
      // Points mapped by the target's inverse (x ties survive the map).
      for (const auto &u : {randomPoints(n, 500 + n), sequencePoints(Scramble::Owen, n, n),
                            latticePoints(n, 600 + n)}) {
        const std::vector<Point2> x = mapped(u, *t);
        EXPECT_NEAR(starDiscrepancy(x, t), bruteStar(x, targetAnchored(*t)), 1e-13)
            << t->spec() << " mapped N=" << n;
      }
      // Unmapped lattice points: ties in both coordinates, 0 and 1.0, and for
      // the disc, points outside its support.
      const std::vector<Point2> ties = latticePoints(n, 700 + n);
      EXPECT_NEAR(starDiscrepancy(ties, t), bruteStar(ties, targetAnchored(*t)), 1e-13)
          << t->spec() << " lattice N=" << n;
    }
  }
}

TEST(MetricStarDiscrepancy, RandomBoxesNeverExceedIt) {
  const BilinearTarget bilinear(1, 2, 0.5, 3);
  TestRng rng(77);
  for (std::size_t n : {1u, 5u, 16u, 50u}) {
    const std::vector<Point2> p = randomPoints(n, 800 + n);
    const std::vector<Point2> q = mapped(p, bilinear);
    const double dUniform = starDiscrepancy(p), dBilinear = starDiscrepancy(q, &bilinear);
    double seenUniform = 0, seenBilinear = 0;
    for (int s = 0; s < 20000; ++s) {
      const double a = rng.uniform(), b = rng.uniform();
      int cp = 0, cq = 0;
      for (std::size_t i = 0; i < n; ++i) {
        cp += p[i].x <= a && p[i].y <= b;
        cq += q[i].x <= a && q[i].y <= b;
      }
      seenUniform = std::max(seenUniform, std::abs(double(cp) / n - a * b));
      seenBilinear =
          std::max(seenBilinear, std::abs(double(cq) / n - bilinear.mass({{0, 0}, {a, b}})));
    }
    EXPECT_LE(seenUniform, dUniform + 1e-14) << "N=" << n;
    EXPECT_LE(seenBilinear, dBilinear + 1e-14) << "N=" << n;
    // ... and the sup is approached: 20000 random boxes get within 15%.
    EXPECT_GT(seenUniform, 0.85 * dUniform) << "N=" << n;
  }
}

// ------------------------------------------------------------ 4. Sobol nets

TEST(MetricSobolStar, UnscrambledPrefixesMatchBruteForce) {
  // Hand-computed: m=0 is the origin alone (box [0,0]^2: 1); m=1 adds (1/2,1/2)
  // ([0,1/2]^2 holds both: 1 - 1/4); m=2 adds (3/4,1/4),(1/4,3/4) ([0,3/4]^2
  // holds all four: 1 - 9/16).
  const double hand[3] = {1.0, 0.75, 0.4375};
  for (int m = 0; m <= 6; ++m) {
    const std::vector<Point2> p = sequencePoints(Scramble::None, 0, std::size_t(1) << m);
    const double d = starDiscrepancy(p);
    EXPECT_NEAR(d, bruteStar(p, uniformAnchored), 1e-15) << "m=" << m;
    if (m < 3) {
      EXPECT_NEAR(d, hand[m], 1e-15) << "m=" << m;
    }
    // The largest coordinate is 1 - 2^-m and the origin is included, so the
    // closed box [0, 1 - 2^-m]^2 holds every point: a lower bound.
    const double h = 1 - std::ldexp(1.0, -m);
    EXPECT_GE(d, 1 - h * h - 1e-15) << "m=" << m;
  }
}

// First k in 0..m for which some elementary interval
// [i 2^-k, (i+1) 2^-k) x [j 2^-(m-k), (j+1) 2^-(m-k)) does not hold exactly
// one of the 2^m points, or -1 if they all do.
int firstNetViolation(std::span<const Point2> p, int m) {
  for (int k = 0; k <= m; ++k) {
    const int nx = 1 << k, ny = 1 << (m - k);
    std::vector<int> hits(std::size_t(nx) * ny, 0);
    for (const Point2 &q : p) {
      const int i = int(std::floor(q.x * nx)), j = int(std::floor(q.y * ny));
      if (i < 0 || i >= nx || j < 0 || j >= ny) return k;
      ++hits[std::size_t(i) * ny + j];
    }
    for (int h : hits)
      if (h != 1) return k;
  }
  return -1;
}

TEST(NetProperty, OwenScrambledSobolIsAZeroMTwoNet) {
  for (std::uint64_t seed : {0u, 1u, 2u, 12345u, 987654321u})
    for (int m = 1; m <= 10; ++m) {
      std::vector<Point2> p(std::size_t(1) << m);
      generatePoints(SequenceOptions{SequenceKind::Sobol, Scramble::Owen, seed}, 0, p);
      EXPECT_EQ(firstNetViolation(p, m), -1) << "seed " << seed << " m=" << m;
      // Other instances through generatePointSet.
      const PointSet set =
          generatePointSet(SequenceOptions{SequenceKind::Sobol, Scramble::Owen, seed}, p.size(), 3);
      for (std::size_t k = 0; k < set.instances(); ++k)
        EXPECT_EQ(firstNetViolation(set.instance(k), m), -1)
            << "seed " << seed << " instance " << k << " m=" << m;
    }
}

TEST(NetProperty, UnscrambledSobolIsANetAndRandomPointsAreNot) {
  for (int m = 1; m <= 10; ++m) {
    const std::vector<Point2> p = sequencePoints(Scramble::None, 0, std::size_t(1) << m);
    EXPECT_EQ(firstNetViolation(p, m), -1) << "m=" << m;
  }
  // The checker can fail: 1024 independent points are (with overwhelming
  // probability) not a net, nor is a net with one point moved.
  std::vector<Point2> rnd(1024);
  generatePoints(SequenceOptions{SequenceKind::Random, Scramble::None, 3}, 0, rnd);
  EXPECT_NE(firstNetViolation(rnd, 10), -1);
  std::vector<Point2> moved = sequencePoints(Scramble::Owen, 4, 256);
  moved[17] = moved[18];
  EXPECT_NE(firstNetViolation(moved, 8), -1);
}

TEST(NetProperty, OwenScrambledPointsAreUniformAcrossSeeds) {
  // Each coordinate of a fixed point index is U[0,1) over seeds: mean 1/2
  // and variance 1/12, within 5 standard errors (sd of the mean
  // sqrt(1/12/S); of the sample variance sqrt((1/80 - 1/144)/S)).
  const int S = 4000;
  const double meanTol = 5 * std::sqrt(1.0 / 12 / S);
  const double varTol = 5 * std::sqrt((1.0 / 80 - 1.0 / 144) / S);
  for (std::size_t index : {0u, 1u, 2u, 5u, 100u}) {
    double sx = 0, sy = 0, sxx = 0, syy = 0;
    std::vector<Point2> p(index + 1);
    for (int s = 0; s < S; ++s) {
      generatePoints(SequenceOptions{SequenceKind::Sobol, Scramble::Owen, std::uint64_t(s)}, 0, p);
      sx += p[index].x;
      sy += p[index].y;
      sxx += p[index].x * p[index].x;
      syy += p[index].y * p[index].y;
    }
    const double mx = sx / S, my = sy / S;
    EXPECT_NEAR(mx, 0.5, meanTol) << "index " << index;
    EXPECT_NEAR(my, 0.5, meanTol) << "index " << index;
    EXPECT_NEAR(sxx / S - mx * mx, 1.0 / 12, varTol) << "index " << index;
    EXPECT_NEAR(syy / S - my * my, 1.0 / 12, varTol) << "index " << index;
  }
  // The same across instances of one seed.
  const PointSet set =
      generatePointSet(SequenceOptions{SequenceKind::Sobol, Scramble::Owen, 9}, 4, S);
  double sx = 0;
  for (std::size_t k = 0; k < set.instances(); ++k) sx += set.instance(k)[3].x;
  EXPECT_NEAR(sx / S, 0.5, meanTol);
}

// ------------------------------------------------------------ periodic L2

// Quadrature over (a, b) pairs of one coordinate: the intervals from a up to
// b on the circle. Off the diagonal a G x G midpoint rule; each diagonal
// cell is split along a = b into two triangles sampled at their centroids
// (below the diagonal the interval wraps and covers nearly everything, above
// it covers nearly nothing), so with points on a 1/G grid every indicator is
// constant on each piece and the lengths are linear. The midpoint rule's
// error on the squared lengths is c / G^2, which Richardson extrapolation
// from G and G / 2 removes.
struct IntervalNode {
  double a, b, w;
};
std::vector<IntervalNode> intervalNodes(int G) {
  std::vector<IntervalNode> nodes;
  const double h = 1.0 / G;
  for (int i = 0; i < G; ++i)
    for (int j = 0; j < G; ++j)
      if (i != j) {
        nodes.push_back({(i + 0.5) * h, (j + 0.5) * h, h * h});
      } else {
        nodes.push_back({(i + 1.0 / 3) * h, (i + 2.0 / 3) * h, h * h / 2});
        nodes.push_back({(i + 2.0 / 3) * h, (i + 1.0 / 3) * h, h * h / 2});
      }
  return nodes;
}

// The definition: the mean over toroidal boxes of (count / N - volume)^2.
double brutePeriodicL2Squared(std::span<const Point2> p, int G) {
  const std::vector<IntervalNode> nodes = intervalNodes(G);
  auto inside = [](double x, const IntervalNode &n) {
    return n.a <= n.b ? (x >= n.a && x <= n.b) : (x >= n.a || x <= n.b);
  };
  auto length = [](const IntervalNode &n) { return n.a <= n.b ? n.b - n.a : 1 - n.a + n.b; };
  const std::size_t m = nodes.size(), N = p.size();
  // in[c][node * N + i]: is point i's coordinate c inside the node's interval
  std::vector<std::vector<char>> in(2, std::vector<char>(m * N));
  for (std::size_t q = 0; q < m; ++q)
    for (std::size_t i = 0; i < N; ++i) {
      in[0][q * N + i] = inside(p[i].x, nodes[q]);
      in[1][q * N + i] = inside(p[i].y, nodes[q]);
    }
  double sum = 0;
  for (std::size_t qx = 0; qx < m; ++qx)
    for (std::size_t qy = 0; qy < m; ++qy) {
      int count = 0;
      for (std::size_t i = 0; i < N; ++i) count += in[0][qx * N + i] & in[1][qy * N + i];
      const double d = count / double(N) - length(nodes[qx]) * length(nodes[qy]);
      sum += nodes[qx].w * nodes[qy].w * d * d;
    }
  return sum;
}

TEST(MetricPeriodicL2, MatchesTheDefinitionByQuadrature) {
  TestRng rng(17);
  for (const std::size_t n : {1, 2, 5}) {
    std::vector<Point2> p(n);
    for (Point2 &q : p)
      q = {std::floor(rng.uniform() * 16) / 16, std::floor(rng.uniform() * 16) / 16};
    const double brute = (4 * brutePeriodicL2Squared(p, 64) - brutePeriodicL2Squared(p, 32)) / 3;
    EXPECT_NEAR(periodicL2Squared(p), brute, 2e-5 * brute) << n;
  }
  // One point: 1/4 - 1/9 whatever its position.
  EXPECT_NEAR(periodicL2Squared(std::vector<Point2>{{0.3, 0.8}}), 0.25 - 1.0 / 9, 1e-15);
}

TEST(MetricPeriodicL2, GradientMatchesFiniteDifferences) {
  std::vector<Point2> p = randomPoints(37, 5);  // N not a power of two
  std::vector<Point2> grad(p.size());
  periodicL2Squared(p, grad);
  const double h = 1e-6;
  for (std::size_t i = 0; i < p.size(); i += 4)
    for (int c = 0; c < 2; ++c) {
      const double keep = p[i][c];
      p[i][c] = keep + h;
      const double plus = periodicL2Squared(p);
      p[i][c] = keep - h;
      const double minus = periodicL2Squared(p);
      p[i][c] = keep;
      EXPECT_NEAR(grad[i][c], (plus - minus) / (2 * h), 1e-7) << i << " " << c;
    }
}

TEST(MetricPeriodicL2, EveryToroidalShiftLeavesItUnchanged) {
  TestRng rng(8);
  const std::vector<Point2> p = sequencePoints(Scramble::Owen, 3, 64);
  const double d = periodicL2(p);
  for (int trial = 0; trial < 5; ++trial) {
    const Point2 s{rng.uniform(), rng.uniform()};
    std::vector<Point2> q(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      q[i] = {wrapUnit(p[i].x + s.x), wrapUnit(p[i].y + s.y)};
    EXPECT_NEAR(periodicL2(q), d, 1e-12);
  }
  // ...which the star discrepancy is not: the test can fail.
  std::vector<Point2> q(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    q[i] = {wrapUnit(p[i].x + 0.3), wrapUnit(p[i].y + 0.6)};
  EXPECT_GT(std::abs(l2asd(q) - l2asd(p)), 1e-4);
}

}  // namespace
}  // namespace nuld
