// The soft box loss against its oracles: the hard loss, the closed-form
// L2asd, central finite differences, and an unculled evaluation.
#include "sampler/loss/soft_box_loss.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "sampler/loss/box_mass.h"
#include "sampler/loss/boxes.h"
#include "sampler/loss/point_grid.h"
#include "sampler/metrics/discrepancy.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/basic_targets.h"

namespace nuld {
namespace {

std::vector<Point2> randomPoints(std::size_t n, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Point2> p(n);
  for (Point2 &q : p) q = {rng.uniform(), rng.uniform()};
  return p;
}

struct Problem {
  std::vector<Box2> boxes;
  std::vector<double> masses;
};

Problem makeProblem(BoxKind kind, std::size_t m, const Target &target, std::uint64_t seed) {
  Rng rng(seed, 1);
  Problem p{std::vector<Box2>(m), std::vector<double>(m)};
  sampleBoxes(kind, rng, p.boxes);
  exactBoxMasses(target, p.boxes, p.masses);
  return p;
}

TEST(SoftBoxLoss, TendsToHardLossAsAlphaGrows) {
  const auto pts = randomPoints(200, 1);
  const UniformTarget uniform;
  const Problem pr = makeProblem(BoxKind::MultipleCorner, 500, uniform, 2);
  const double hard = hardBoxLoss(pts, pr.boxes, pr.masses);
  // Box by box, |r_soft - r_hard| <= e_m = (1/N) sum_i |sigma(alpha d) - 1(d >= 0)|,
  // so |L_soft - L_hard| <= (1/M) sum_m e_m (2 |r_hard| + e_m). The gap is not
  // monotone in alpha (a point 1e-6 from a side matters until alpha ~ 1e7), so
  // check the bound at every alpha and the limit at the end.
  const double N = double(pts.size());
  for (double alpha : {10.0, 100.0, 1e3, 1e4, 1e5, 1e6, 1e7, 1e9}) {
    double bound = 0;
    for (std::size_t m = 0; m < pr.boxes.size(); ++m) {
      const Box2 &b = pr.boxes[m];
      double e = 0, inside = 0;
      for (const Point2 &p : pts) {
        const double d = std::min({p.x - b.lo.x, b.hi.x - p.x, p.y - b.lo.y, b.hi.y - p.y});
        e += std::abs(safeSigmoid(alpha * d) - (d >= 0 ? 1.0 : 0.0));
        inside += d >= 0;
      }
      e /= N;
      bound += e * (2 * std::abs(inside / N - pr.masses[m]) + e);
    }
    bound /= double(pr.boxes.size());
    const double gap = std::abs(softBoxLoss(pts, pr.boxes, pr.masses, {alpha}) - hard);
    EXPECT_LE(gap, bound * (1 + 1e-9) + 1e-16) << "alpha " << alpha;
    if (alpha == 1e9) {
      EXPECT_LT(gap, 1e-9 * hard);
    }
  }
}

// L2asd^2 is the exact expectation of the hard multiple-corner box loss.
TEST(SoftBoxLoss, MeanOverSampledBoxesMatchesL2asdSquared) {
  for (std::size_t n : {1u, 37u, 256u}) {
    SequenceOptions o{SequenceKind::Sobol, Scramble::Owen, 5};
    const PointSet set = generatePointSet(o, n, 1);
    const auto pts = set.instance(0);
    const UniformTarget uniform;
    const std::size_t M = 200000;
    const Problem pr = makeProblem(BoxKind::MultipleCorner, M, uniform, 3 + n);
    // Per-box squared residuals give the Monte Carlo standard error.
    double sum = 0, sum2 = 0;
    for (std::size_t m = 0; m < M; ++m) {
      const double r = hardBoxLoss(pts, std::span(&pr.boxes[m], 1), std::span(&pr.masses[m], 1));
      sum += r;
      sum2 += r * r;
    }
    const double mean = sum / M, se = std::sqrt((sum2 / M - mean * mean) / M);
    const double exact = std::pow(l2asd(pts), 2);
    EXPECT_NEAR(mean, exact, 4 * se) << "N = " << n;
    const double soft = softBoxLoss(pts, pr.boxes, pr.masses, {1e7});
    EXPECT_NEAR(soft, exact, 4 * se) << "N = " << n;
  }
}

TEST(SoftBoxLoss, GradientMatchesCentralDifferences) {
  const QuarterDiscTarget disc;
  for (BoxKind kind : {BoxKind::MultipleCorner, BoxKind::Anchored, BoxKind::TwoPoint})
    for (double alpha : {20.0, 300.0}) {
      auto pts = randomPoints(24, 11);
      const Problem pr = makeProblem(kind, 80, disc, 12);
      std::vector<Point2> grad(pts.size());
      softBoxLoss(pts, pr.boxes, pr.masses, {alpha}, grad);
      const double h = 1e-6 / (alpha / 20);
      for (std::size_t i = 0; i < pts.size(); ++i)
        for (int k = 0; k < 2; ++k) {
          const double x0 = pts[i][k];
          pts[i][k] = x0 + h;
          const double up = softBoxLoss(pts, pr.boxes, pr.masses, {alpha});
          pts[i][k] = x0 - h;
          const double down = softBoxLoss(pts, pr.boxes, pr.masses, {alpha});
          pts[i][k] = x0;
          const double fd = (up - down) / (2 * h);
          EXPECT_NEAR(grad[i][k], fd, 1e-5 * std::abs(fd) + 1e-9)
              << toString(kind) << " alpha " << alpha << " point " << i << " axis " << k;
        }
    }
}

// The parallel blocks draw exactly the sequential boxes, and leave the
// generator where the sequential draws would.
TEST(SampleBoxes, ParallelBlocksEqualSequentialDraws) {
  for (BoxKind kind : {BoxKind::MultipleCorner, BoxKind::Anchored, BoxKind::TwoPoint}) {
    Rng parallel(5, 9), sequential(5, 9);
    std::vector<Box2> boxes(5000);
    sampleBoxes(kind, parallel, boxes);
    for (std::size_t m = 0; m < boxes.size(); ++m) {
      const Box2 b = sampleBox(kind, sequential);
      ASSERT_TRUE(b.lo.x == boxes[m].lo.x && b.lo.y == boxes[m].lo.y && b.hi.x == boxes[m].hi.x &&
                  b.hi.y == boxes[m].hi.y)
          << toString(kind) << " box " << m;
    }
    EXPECT_EQ(parallel.nextBits(), sequential.nextBits()) << toString(kind);
  }
}

// Every kernel against the definition (no cutoff, culling or vectors), on
// uniform and clustered points: the loss and gradient to 1e-12 relative.
TEST(SoftBoxLoss, KernelsMatchTheReference) {
  const QuarterDiscTarget disc;
  Rng rng(31);
  // Clustered: most points in a small corner, as a peaked target leaves them.
  std::vector<Point2> clustered(333);
  for (Point2 &p : clustered)
    p = rng.uniform() < 0.8 ? Point2{0.6 + 0.05 * rng.uniform(), 0.3 + 0.02 * rng.uniform()}
                            : Point2{rng.uniform(), rng.uniform()};
  const std::vector<std::vector<Point2>> sets = {randomPoints(1, 40), randomPoints(333, 41),
                                                 clustered};
  for (const auto &pts : sets)
    for (BoxKind kind : {BoxKind::MultipleCorner, BoxKind::Anchored, BoxKind::TwoPoint}) {
      const Problem pr = makeProblem(kind, 300, disc, 42);
      for (double alpha : {20.0, 600.0, 6000.0, 1e4}) {
        std::vector<Point2> ref(pts.size());
        const double expected = softBoxLossReference(pts, pr.boxes, pr.masses, alpha, ref);
        double scale = 0;
        for (const Point2 &g : ref) scale = std::max({scale, std::abs(g.x), std::abs(g.y)});
        for (SoftBoxKernel kernel :
             {SoftBoxKernel::Automatic, SoftBoxKernel::Direct, SoftBoxKernel::Factored}) {
          std::vector<Point2> grad(pts.size());
          const double loss = softBoxLoss(pts, pr.boxes, pr.masses, {alpha, 36, kernel}, grad);
          const std::string what = toString(kind) + " N " + std::to_string(pts.size()) + " alpha " +
                                   std::to_string(alpha) + " kernel " + std::to_string(int(kernel));
          EXPECT_NEAR(loss, expected, 1e-12 * expected) << what;
          for (std::size_t i = 0; i < pts.size(); ++i) {
            ASSERT_NEAR(grad[i].x, ref[i].x, 1e-12 * scale) << what << " point " << i;
            ASSERT_NEAR(grad[i].y, ref[i].y, 1e-12 * scale) << what << " point " << i;
          }
        }
      }
    }
}

// Points beyond the cutoff from every side get no gradient at all, whichever
// kernel runs, and no box side at infinity (multiple-corner boxes) or far
// away leaves a tiny slope: the factored kernel's products stay normal
// numbers (subnormal ones cost x86 cores microcode assists).
TEST(SoftBoxLoss, PointsBeyondTheCutoffHaveExactlyZeroGradient) {
  const double alpha = 600, delta = 36 / alpha;
  // Two points deep inside or outside every box: the boxes' finite sides
  // stay more than delta from them.
  const std::vector<Point2> pts = {{0.05, 0.05}, {0.95, 0.95}};
  std::vector<Box2> boxes;
  const double inf = std::numeric_limits<double>::infinity();
  for (double c : {0.3, 0.5, 0.7}) {
    boxes.push_back({{-inf, -inf}, {c, c}});
    boxes.push_back({{c, -inf}, {inf, c + 0.05}});
    boxes.push_back({{c, c}, {inf, inf}});
  }
  for (const Box2 &b : boxes)
    for (const Point2 &p : pts)
      for (double side : {b.lo.x - p.x, b.hi.x - p.x, b.lo.y - p.y, b.hi.y - p.y})
        ASSERT_GT(std::abs(side), delta);
  const std::vector<double> masses(boxes.size(), 0.3);
  for (SoftBoxKernel kernel : {SoftBoxKernel::Direct, SoftBoxKernel::Factored}) {
    std::vector<Point2> grad(pts.size(), Point2{1, 1});
    const double loss = softBoxLoss(pts, boxes, masses, {alpha, 36, kernel}, grad);
    EXPECT_NEAR(loss, softBoxLossReference(pts, boxes, masses, alpha), 1e-12 * loss);
    for (const Point2 &g : grad) {
      EXPECT_EQ(g.x, 0.0) << "kernel " << int(kernel);
      EXPECT_EQ(g.y, 0.0) << "kernel " << int(kernel);
    }
  }
}

TEST(SoftBoxLoss, FactoredKernelRefusesWhatItCannotRepresent) {
  const UniformTarget u;
  const Problem pr = makeProblem(BoxKind::MultipleCorner, 10, u, 1);
  std::vector<Point2> pts = randomPoints(10, 2);
  EXPECT_THROW(softBoxLoss(pts, pr.boxes, pr.masses, {2e4, 36, SoftBoxKernel::Factored}),
               std::invalid_argument);
  pts[3].x = 1.5;  // outside the unit square: the automatic choice falls back
  EXPECT_THROW(softBoxLoss(pts, pr.boxes, pr.masses, {20, 36, SoftBoxKernel::Factored}),
               std::invalid_argument);
  const double automatic = softBoxLoss(pts, pr.boxes, pr.masses, {20});
  EXPECT_NEAR(automatic, softBoxLossReference(pts, pr.boxes, pr.masses, 20), 1e-12 * automatic);
}

// Band culling must not change the result: compare with a cutoff so large
// that every pair is evaluated.
TEST(SoftBoxLoss, BandCullingMatchesFullEvaluation) {
  const BilinearTarget target(1, 2, 0.5, 3);
  for (BoxKind kind : {BoxKind::MultipleCorner, BoxKind::Anchored, BoxKind::TwoPoint})
    for (double alpha : {20.0, 2000.0, 6000.0}) {
      const auto pts = randomPoints(777, 21);
      const Problem pr = makeProblem(kind, 400, target, 22);
      std::vector<Point2> g1(pts.size()), g2(pts.size());
      const double culled = softBoxLoss(pts, pr.boxes, pr.masses, {alpha}, g1);
      const double full = softBoxLoss(pts, pr.boxes, pr.masses, {alpha, 1e300}, g2);
      EXPECT_NEAR(culled, full, 1e-13 + 1e-12 * full);
      double scale = 0;
      for (const Point2 &g : g2) scale = std::max({scale, std::abs(g.x), std::abs(g.y)});
      for (std::size_t i = 0; i < pts.size(); ++i) {
        ASSERT_NEAR(g1[i].x, g2[i].x, 1e-12 * scale);
        ASSERT_NEAR(g1[i].y, g2[i].y, 1e-12 * scale);
      }
    }
}

TEST(SoftBoxLoss, DeterministicAcrossCalls) {
  const auto pts = randomPoints(2048, 5);
  const UniformTarget u;
  const Problem pr = makeProblem(BoxKind::MultipleCorner, 4096, u, 6);
  std::vector<Point2> g1(pts.size()), g2(pts.size());
  const double a = softBoxLoss(pts, pr.boxes, pr.masses, {600}, g1);
  const double b = softBoxLoss(pts, pr.boxes, pr.masses, {600}, g2);
  EXPECT_EQ(a, b);
  EXPECT_EQ(g1, g2);
}

TEST(SoftBoxLoss, StableAtExtremes) {
  EXPECT_EQ(safeSigmoid(1e4), 1.0);
  EXPECT_EQ(safeSigmoid(-1e4), 0.0);
  EXPECT_EQ(safeSigmoid(-1e308), 0.0);
  EXPECT_EQ(safeSigmoid(0), 0.5);
  const UniformTarget u;
  // alpha * d = +-1e4 and beyond; a point exactly on a box side.
  std::vector<Point2> pts = {{0.5, 0.5}, {0.25, 0.75}, {1.0, 0.0}, {0.0, 1.0}};
  std::vector<Box2> boxes = {{{-INFINITY, -INFINITY}, {0.5, 0.5}},
                             {{0.2, 0.2}, {0.2, 0.2}},  // zero area, zero mass
                             {{0.5 - 1e-4, 0.0}, {0.5 + 1e-4, 1.0}}};
  std::vector<double> masses(boxes.size());
  exactBoxMasses(u, boxes, masses);
  EXPECT_EQ(masses[1], 0.0);
  for (double alpha : {1e-3, 1.0, 1e4, 1e8, 1e12}) {
    std::vector<Point2> g(pts.size());
    const double l = softBoxLoss(pts, boxes, masses, {alpha}, g);
    EXPECT_TRUE(std::isfinite(l)) << alpha;
    for (const Point2 &q : g) EXPECT_TRUE(isFinite(q)) << alpha;
  }
  // N = 1.
  std::vector<Point2> one = {{0.3, 0.3}}, g1(1);
  const Problem pr = makeProblem(BoxKind::TwoPoint, 100, u, 9);
  EXPECT_TRUE(std::isfinite(softBoxLoss(one, pr.boxes, pr.masses, {6000}, g1)));
  EXPECT_TRUE(isFinite(g1[0]));
}

TEST(SoftBoxLoss, RejectsBadInput) {
  std::vector<Point2> pts = {{0.5, NAN}};
  std::vector<Box2> boxes = {{{0, 0}, {1, 1}}};
  std::vector<double> masses = {1.0};
  EXPECT_THROW(softBoxLoss(pts, boxes, masses, {20}), std::invalid_argument);
  pts[0].y = 0.5;
  EXPECT_THROW(softBoxLoss(pts, boxes, std::vector<double>{}, {20}), std::invalid_argument);
  EXPECT_THROW(softBoxLoss(pts, boxes, masses, {0}), std::invalid_argument);
  std::vector<Point2> wrongGrad(3);
  EXPECT_THROW(softBoxLoss(pts, boxes, masses, {20}, wrongGrad), std::invalid_argument);
}

TEST(PointGrid, BoxSumMatchesBruteForce) {
  const auto pts = randomPoints(1000, 3);
  std::vector<double> w(pts.size());
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = 1 + (i % 7);
  const PointGrid counted(pts), weighted(pts, w);
  Rng rng(4);
  for (int t = 0; t < 300; ++t) {
    const Box2 b = sampleBox(BoxKind::TwoPoint, rng);
    double c = 0, s = 0;
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (b.contains(pts[i])) c += 1, s += w[i];
    ASSERT_EQ(counted.boxSum(b), c);
    ASSERT_NEAR(weighted.boxSum(b), s, 1e-9);
  }
}

TEST(MonteCarloBoxMass, AgreesWithExactMassWithinError) {
  const QuarterDiscTarget disc;
  const std::size_t K = 1 << 17;
  MonteCarloBoxMass mc(disc, K);
  Rng rng(8);
  const Problem pr = makeProblem(BoxKind::MultipleCorner, 200, disc, 9);
  std::vector<double> est(pr.boxes.size());
  mc.estimate(pr.boxes, est, rng);
  for (std::size_t m = 0; m < est.size(); ++m) {
    // Weights are 4/pi on the disc: binomial error of the uniform count.
    const double area = pr.boxes[m].clipped().area() > 0 ? pr.masses[m] * std::numbers::pi / 4 : 0;
    const double se = 4 / std::numbers::pi * std::sqrt(area * (1 - area) / K) + 1e-12;
    EXPECT_NEAR(est[m], pr.masses[m], 5 * se) << m;
  }
}

}  // namespace
}  // namespace nuld
