// Metrics: discrepancies against exact brute force, the net property of
// Sobol points, power spectra and integration estimates.
//
// The brute-force references here share no code with the library: the L2
// discrepancies are integrated exactly cell by cell (the local discrepancy is
// a polynomial between consecutive point coordinates), D* is a direct O(N^3)
// search over the critical boxes, and spectra are summed term by term.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "sampler/metrics/discrepancy.h"
#include "sampler/metrics/integration.h"
#include "sampler/metrics/spectrum.h"
#include "sampler/point.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/grid_target.h"

namespace nuld {
namespace {

// ------------------------------------------------------------------ helpers

// Test-side random numbers, independent of the library's generators.
class TestRng {
 public:
  explicit TestRng(std::uint64_t seed) : gen_(seed) {}
  double uniform() { return double(gen_() >> 11) * 0x1.0p-53; }
  int uniformInt(int n) { return int(gen_() % std::uint64_t(n)); }

 private:
  std::mt19937_64 gen_;
};

std::vector<Point2> randomPoints(std::size_t n, std::uint64_t seed) {
  TestRng rng(seed);
  std::vector<Point2> p(n);
  for (Point2 &q : p) q = {rng.uniform(), rng.uniform()};
  return p;
}

// Points on the grid {0, 1/8, ..., 1}: many ties in x and y, duplicates,
// points at 0 and at exactly 1.
std::vector<Point2> latticePoints(std::size_t n, std::uint64_t seed) {
  TestRng rng(seed);
  std::vector<Point2> p(n);
  for (Point2 &q : p) q = {rng.uniformInt(9) / 8.0, rng.uniformInt(9) / 8.0};
  return p;
}

std::vector<Point2> sequencePoints(Scramble scramble, std::uint64_t seed, std::size_t n) {
  std::vector<Point2> p(n);
  generatePoints(SequenceOptions{SequenceKind::Sobol, scramble, seed}, 0, p);
  return p;
}

// The box spanned by corner (cx, cy) in {0,1}^2 and (a, b):
// [0,a] or [a,1] in x, [0,b] or [b,1] in y.
Box2 cornerBox(int cx, int cy, double a, double b) {
  return {{cx ? a : 0.0, cy ? b : 0.0}, {cx ? 1.0 : a, cy ? 1.0 : b}};
}

using CornerMeasure = std::function<double(int cx, int cy, double a, double b)>;

double uniformCornerMeasure(int cx, int cy, double a, double b) {
  return (cx ? 1 - a : a) * (cy ? 1 - b : b);
}

CornerMeasure targetCornerMeasure(const Target &t) {
  return [&t](int cx, int cy, double a, double b) { return t.mass(cornerBox(cx, cy, a, b)); };
}

std::vector<double> breakpoints(std::span<const Point2> p, int axis,
                                std::vector<double> v /* extra breakpoints */) {
  v.push_back(0.0);
  v.push_back(1.0);
  for (const Point2 &q : p) v.push_back(std::clamp(q[axis], 0.0, 1.0));
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// Exact integral over (a, b) in [0,1]^2 of (count/N - mu)^2 for the boxes of
// one corner. Between consecutive point coordinates the count is constant
// (read at the cell centre) and mu is a polynomial of degree <= 2 in each of
// a and b for the uniform and bilinear targets (and, between the extra
// breakpoints, for step and grid targets), so the integrand has degree <= 4
// per axis and 3-point Gauss-Legendre on every cell is exact.
double exactCornerIntegral(std::span<const Point2> p, int cx, int cy, const CornerMeasure &mu,
                           const std::vector<double> &xBreaks, const std::vector<double> &yBreaks) {
  const std::vector<double> xs = breakpoints(p, 0, xBreaks), ys = breakpoints(p, 1, yBreaks);
  const double N = double(p.size());
  const double r = std::sqrt(0.6);
  const double node[3] = {-r, 0.0, r}, weight[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  double total = 0;
  for (std::size_t i = 0; i + 1 < xs.size(); ++i)
    for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
      const double x0 = xs[i], x1 = xs[i + 1], y0 = ys[j], y1 = ys[j + 1];
      const double ac = 0.5 * (x0 + x1), bc = 0.5 * (y0 + y1);
      const Box2 centre = cornerBox(cx, cy, ac, bc);
      int count = 0;
      for (const Point2 &q : p) count += centre.contains(q);
      const double c = count / N;
      double cell = 0;
      for (int u = 0; u < 3; ++u)
        for (int v = 0; v < 3; ++v) {
          const double a = ac + 0.5 * (x1 - x0) * node[u];
          const double b = bc + 0.5 * (y1 - y0) * node[v];
          const double d = c - mu(cx, cy, a, b);
          cell += weight[u] * weight[v] * d * d;
        }
      total += cell * 0.25 * (x1 - x0) * (y1 - y0);
    }
  return total;
}

double exactL2Star(std::span<const Point2> p, const CornerMeasure &mu = uniformCornerMeasure,
                   const std::vector<double> &xBreaks = {},
                   const std::vector<double> &yBreaks = {}) {
  return std::sqrt(exactCornerIntegral(p, 0, 0, mu, xBreaks, yBreaks));
}

double exactL2asd(std::span<const Point2> p, const CornerMeasure &mu = uniformCornerMeasure,
                  const std::vector<double> &xBreaks = {},
                  const std::vector<double> &yBreaks = {}) {
  double s = 0;
  for (int cx = 0; cx < 2; ++cx)
    for (int cy = 0; cy < 2; ++cy) s += exactCornerIntegral(p, cx, cy, mu, xBreaks, yBreaks);
  return std::sqrt(s / 4);
}

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

std::vector<Point2> mapped(std::span<const Point2> u, const Target &t) {
  std::vector<Point2> x;
  for (const Point2 &q : u) x.push_back(t.invert(q).x);
  return x;
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

// ------------------------------------------------- 5. grid L2 against exact

TEST(MetricGridL2, UniformTargetIsExactAtAnyResolution) {
  // F(a, b) = ab is bilinear, so its bilinear interpolant on any grid is F.
  const UniformTarget uniform;
  std::vector<Point2> edges = randomPoints(12, 51);
  for (const Point2 e : {Point2{0.3, 0.9999}, Point2{0.9999, 0.3}, Point2{0.3, 1.0},
                         Point2{1.0, 0.6}, Point2{1.0, 1.0}, Point2{0, 0}})
    edges.push_back(e);
  const std::vector<std::vector<Point2>> sets = {randomPoints(1, 52),
                                                 randomPoints(16, 53),
                                                 latticePoints(20, 54),
                                                 sequencePoints(Scramble::Owen, 55, 33),
                                                 sequencePoints(Scramble::None, 0, 16),
                                                 edges};
  // Only rounding differs: relative 1e-10 leaves ~100x margin over the
  // largest deviation measured (9e-13, res = 1024, from summing 4 res^2 cell
  // terms that cancel against the cross and pair terms).
  for (const auto &p : sets)
    for (int res : {1, 2, 7, 64, 256, 1024}) {
      const double star = l2StarDiscrepancy(p), asd = l2asd(p);
      EXPECT_NEAR(nonuniformL2Star(p, uniform, res), star, 1e-10 * star)
          << "N=" << p.size() << " res " << res;
      EXPECT_NEAR(nonuniformL2asd(p, uniform, res), asd, 1e-10 * asd)
          << "N=" << p.size() << " res " << res;
    }
}

TEST(MetricGridL2, GridTargetIsExact) {
  // Piecewise-constant density on uneven cells: inside a cell the box mass is
  // bilinear in (a, b), so the exact cell integration with the grid edges as
  // extra breakpoints is exact; the library uses the target's own cells.
  const std::vector<double> xe = {0, 0.2, 0.55, 1}, ye = {0, 0.4, 0.7, 0.85, 1};
  const std::vector<double> density = {1, 3, 0.5, 2, 0, 1, 4, 1, 2, 0.25, 3, 1};
  const GridTarget grid(xe, ye, density, "test-grid", Domain::Square, "metrics_test");
  const CornerMeasure mu = targetCornerMeasure(grid);
  for (const auto &u : {randomPoints(16, 56), latticePoints(20, 57)}) {
    const std::vector<Point2> p = mapped(u, grid);
    EXPECT_NEAR(nonuniformL2Star(p, grid), exactL2Star(p, mu, xe, ye), 1e-12);
    EXPECT_NEAR(nonuniformL2asd(p, grid), exactL2asd(p, mu, xe, ye), 1e-12);
    EXPECT_NEAR(nonuniformL2Star(u, grid), exactL2Star(u, mu, xe, ye), 1e-12);
    EXPECT_NEAR(nonuniformL2asd(u, grid), exactL2asd(u, mu, xe, ye), 1e-12);
  }
}

TEST(MetricGridL2, ConvergesToExactValuesWithResolution) {
  // The grid L2 integrates against the bilinear interpolant of the target's
  // CDF (not the midpoint rule), so the error is O(1/res^2) for smooth CDFs
  // and zero for uniform ones. Measured relative errors |grid - exact| / exact,
  // N = 16, sets {random 61, random 62, Owen Sobol 63, Sobol}, res 64/256/1024:
  //   uniform (vs Warnock / closed-form l2asd), worst over the sets:
  //     L2*   2.4e-14  6.7e-14  4.1e-13   L2asd 5.8e-14  4.9e-13  8.9e-13 (rounding)
  //   bilinear:1,2,0.5,3          L2*                         L2asd
  //     set 0             2.3e-5  1.4e-6  8.9e-8      5.0e-6  3.2e-7  2.0e-8
  //     set 1             6.4e-5  4.0e-6  2.5e-7      6.9e-5  4.3e-6  2.7e-7
  //     set 2             1.3e-4  7.9e-6  4.9e-7      4.1e-5  2.5e-6  1.6e-7
  //     set 3             1.5e-4  9.6e-6  6.0e-7      1.4e-4  8.8e-6  5.5e-7
  //   step:1/3,1,3 (CDF kink inside a grid cell)
  //     set 0             1.2e-4  7.2e-6  4.5e-7      1.1e-4  6.5e-6  4.0e-7
  //     set 1             8.5e-6  2.9e-7  1.5e-8      3.2e-5  2.1e-6  1.4e-7
  //     set 2             2.9e-4  2.1e-5  1.4e-6      2.6e-4  2.0e-5  1.3e-6
  //     set 3             5.7e-5  4.2e-6  2.7e-7      1.1e-4  7.5e-6  4.8e-7
  // Every x4 in res divides the error by 13-29, i.e. C / res^2 with C <= 1.5.
  // Asserted: relative error < 3e-6 at res = 1024 (C <= 3, 2x the worst
  // measured; a first-order rule with the res = 64 errors above would sit
  // near 2e-5) and a drop by > 8 (more than first order's 4) per x4 in res.
  const BilinearTarget bilinear(1, 2, 0.5, 3);
  const double x0 = 1.0 / 3;  // not a grid node: F has a kink inside a cell
  const StepTarget step(x0, 1, 3);
  const std::vector<std::vector<Point2>> sets = {randomPoints(16, 61), randomPoints(16, 62),
                                                 sequencePoints(Scramble::Owen, 63, 16),
                                                 sequencePoints(Scramble::None, 0, 16)};
  struct Case {
    const Target *target;
    std::vector<double> xBreaks;
  };
  for (const Case &c : {Case{&bilinear, {}}, Case{&step, {x0}}}) {
    const CornerMeasure mu = targetCornerMeasure(*c.target);
    for (std::size_t s = 0; s < sets.size(); ++s) {
      const std::vector<Point2> p = mapped(sets[s], *c.target);
      const double star = exactL2Star(p, mu, c.xBreaks), asd = exactL2asd(p, mu, c.xBreaks);
      double err[2][3];
      const int resolutions[3] = {64, 256, 1024};
      for (int r = 0; r < 3; ++r) {
        err[0][r] = std::abs(nonuniformL2Star(p, *c.target, resolutions[r]) - star) / star;
        err[1][r] = std::abs(nonuniformL2asd(p, *c.target, resolutions[r]) - asd) / asd;
      }
      for (int m = 0; m < 2; ++m) {
        EXPECT_LT(err[m][2], 3e-6) << c.target->spec() << " set " << s << " metric " << m;
        // Second order: x4 resolution must cut the error by clearly more
        // than the x4 of a first-order rule.
        EXPECT_GT(err[m][1], 8 * err[m][2]) << c.target->spec() << " set " << s;
        EXPECT_GT(err[m][0], 8 * err[m][1]) << c.target->spec() << " set " << s;
      }
    }
  }
}

// ------------------------------------------------------- 6. power spectrum

TEST(MetricSpectrum, SinglePointIsFlat) {
  for (const Point2 q : {Point2{0, 0}, Point2{0.3, 0.77}, Point2{0.999, 0.123456789}}) {
    const Point2 p[1] = {q};
    const PowerSpectrum ps = powerSpectrum(p, 24);
    ASSERT_EQ(ps.halfSize, 24);
    ASSERT_EQ(ps.power.size(), 49u * 49u);
    for (double v : ps.power) ASSERT_NEAR(v, 1.0, 1e-12);
    for (double v : ps.radial) ASSERT_NEAR(v, 1.0, 1e-12);
  }
}

TEST(MetricSpectrum, MatchesDirectSumsDcAndRings) {
  const std::vector<Point2> p = randomPoints(57, 71);
  const int K = 10;
  const PowerSpectrum ps = powerSpectrum(p, K);
  const double N = double(p.size());
  for (int ky = -K; ky <= K; ++ky)
    for (int kx = -K; kx <= K; ++kx) {
      double re = 0, im = 0;
      for (const Point2 &q : p) {
        const double t = -2 * std::numbers::pi * (kx * q.x + ky * q.y);
        re += std::cos(t);
        im += std::sin(t);
      }
      EXPECT_NEAR(ps.at(kx, ky), (re * re + im * im) / N, 1e-10) << kx << "," << ky;
      EXPECT_NEAR(ps.at(kx, ky), ps.at(-kx, -ky), 1e-10);  // real points: P(k) = P(-k)
    }
  EXPECT_NEAR(ps.at(0, 0), N, 1e-10);
  ASSERT_EQ(ps.radial.size(), std::size_t(K + 1));
  EXPECT_NEAR(ps.radial[0], N, 1e-10);
  // Rings |k| in [r - 1/2, r + 1/2), i.e. (2r - 1)^2 <= 4|k|^2 < (2r + 1)^2.
  for (int r = 0; r <= K; ++r) {
    double sum = 0;
    int count = 0;
    for (int ky = -K; ky <= K; ++ky)
      for (int kx = -K; kx <= K; ++kx) {
        const int k4 = 4 * (kx * kx + ky * ky);
        if ((2 * r - 1) * (2 * r - 1) * (r > 0) <= k4 && k4 < (2 * r + 1) * (2 * r + 1)) {
          sum += ps.at(kx, ky);
          ++count;
        }
      }
    EXPECT_NEAR(ps.radial[r], sum / count, 1e-10) << "ring " << r;
  }
}

TEST(MetricSpectrum, RandomPointsAverageToOneAwayFromDc) {
  // For N independent uniform points E P(k) = 1 at every k != 0. Mean over
  // 16 sets x 840 non-DC frequencies (420 independent, P(k) = P(-k)), each
  // P(k) roughly exponential with sd ~1: sd of the mean ~ 1/sqrt(6720) ~ 0.012.
  const int K = 14, sets = 16;
  PointSet set;
  set.n = 128;
  for (int s = 0; s < sets; ++s) {
    const std::vector<Point2> p = randomPoints(set.n, 1000 + s);
    set.points.insert(set.points.end(), p.begin(), p.end());
  }
  const PowerSpectrum avg = averagePowerSpectrum(set, K);
  double total = 0;
  int count = 0;
  for (int ky = -K; ky <= K; ++ky)
    for (int kx = -K; kx <= K; ++kx)
      if (kx != 0 || ky != 0) {
        total += avg.at(kx, ky);
        ++count;
      }
  EXPECT_NEAR(total / count, 1.0, 0.06);
  EXPECT_NEAR(avg.at(0, 0), 128.0, 1e-9);
  EXPECT_NEAR(avg.radial[0], 128.0, 1e-9);
  // The average is the mean of the instance spectra.
  const PowerSpectrum first = powerSpectrum(set.instance(0), K);
  double sumAt = 0;
  for (std::size_t k = 0; k < set.instances(); ++k)
    sumAt += powerSpectrum(set.instance(k), K).at(3, -2);
  EXPECT_NEAR(avg.at(3, -2), sumAt / sets, 1e-10);
  EXPECT_NE(avg.at(3, -2), first.at(3, -2));
}

// ---------------------------------------------------------- 7. integration

TEST(MetricIntegration, UniformTargetGivesThePlainMean) {
  const UniformTarget uniform;
  const std::vector<Point2> p = randomPoints(500, 81);
  for (const char *name : {"step", "disc", "bilinear", "gaussian"}) {
    const TestIntegrand ti = makeTestIntegrand(name);
    double sum = 0;
    for (const Point2 &q : p) sum += ti.f(q);
    EXPECT_NEAR(estimateIntegral(p, uniform, ti.f), sum / p.size(), 1e-15) << name;
  }
}

TEST(MetricIntegration, NonUniformTargetIsImportanceSampling) {
  const BilinearTarget bilinear(1, 2, 0.5, 3);
  const QuarterDiscTarget disc;
  // f proportional to the density: every term is the constant.
  const std::vector<Point2> u = randomPoints(200, 91);
  const std::vector<Point2> x = mapped(u, bilinear);
  EXPECT_NEAR(estimateIntegral(x, bilinear, [&](Point2 q) { return 3 * bilinear.pdf(q); }), 3.0,
              1e-12);
  // Zero-density points contribute nothing but still count in N.
  const std::vector<Point2> two = {{0.9, 0.9}, {0.1, 0.1}};
  EXPECT_NEAR(estimateIntegral(two, disc, [](Point2) { return 1.0; }), 0.5 * std::numbers::pi / 4,
              1e-15);
  // Unbiased: within 5 standard errors of the exact integral.
  const std::vector<Point2> many = mapped(randomPoints(20000, 92), bilinear);
  for (const char *name : {"bilinear", "gaussian", "step"}) {
    const TestIntegrand ti = makeTestIntegrand(name);
    double s = 0, s2 = 0;
    for (const Point2 &q : many) {
      const double w = ti.f(q) / bilinear.pdf(q);
      s += w;
      s2 += w * w;
    }
    const double n = double(many.size()), se = std::sqrt((s2 / n - (s / n) * (s / n)) / n);
    EXPECT_NEAR(estimateIntegral(many, bilinear, ti.f), ti.integral, 5 * se) << name;
  }
}

TEST(MetricIntegration, TestIntegrandsMatchNumericalIntegration) {
  // Midpoint rule on an n x n grid. Smooth integrands: error <= (h^2/24)
  // (max|f_xx| + max|f_yy|) <= 2 * 44.5 / 24 / n^2 < 1e-6 for n = 2001
  // (gaussian: |f''| <= 1/s^2 = 44.5; bilinear: 0, exact). Indicators: only
  // cells cut by the boundary (a line or a quarter circle, < 2n cells) err,
  // by at most their area: error <= 2n / n^2 = 1e-3.
  const int n = 2001;
  for (const char *name : {"step", "disc", "bilinear", "gaussian"}) {
    const TestIntegrand ti = makeTestIntegrand(name);
    EXPECT_EQ(ti.name, name);
    double sum = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) sum += ti.f({(i + 0.5) / n, (j + 0.5) / n});
    const double smooth = std::string(name) == "bilinear" || std::string(name) == "gaussian";
    EXPECT_NEAR(ti.integral, sum / (double(n) * n), smooth ? 1e-6 : 1e-3) << name;
  }
  EXPECT_DOUBLE_EQ(makeTestIntegrand("step").integral, 0.5);
  EXPECT_DOUBLE_EQ(makeTestIntegrand("disc").integral, std::numbers::pi / 4);
  EXPECT_DOUBLE_EQ(makeTestIntegrand("bilinear").integral, 0.25);
  EXPECT_THROW(makeTestIntegrand("cosine"), std::invalid_argument);
}

// ---------------------------------------------------------------- 8. errors

TEST(MetricErrors, EmptyPointSetsThrow) {
  const std::span<const Point2> none;
  const UniformTarget uniform;
  EXPECT_THROW(l2StarDiscrepancy(none), std::invalid_argument);
  EXPECT_THROW(l2asd(none), std::invalid_argument);
  EXPECT_THROW(starDiscrepancy(none), std::invalid_argument);
  EXPECT_THROW(starDiscrepancy(none, &uniform), std::invalid_argument);
  EXPECT_THROW(nonuniformL2Star(none, uniform), std::invalid_argument);
  EXPECT_THROW(nonuniformL2asd(none, uniform), std::invalid_argument);
  EXPECT_THROW(powerSpectrum(none, 4), std::invalid_argument);
  EXPECT_THROW(estimateIntegral(none, uniform, [](Point2) { return 1.0; }), std::invalid_argument);
  // Invalid sizes too.
  const Point2 one[1] = {{0.5, 0.5}};
  EXPECT_THROW(nonuniformL2Star(one, uniform, 0), std::invalid_argument);
  EXPECT_THROW(nonuniformL2asd(one, uniform, -3), std::invalid_argument);
  EXPECT_THROW(powerSpectrum(one, 0), std::invalid_argument);
}

}  // namespace
}  // namespace nuld
