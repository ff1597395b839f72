// Tests of the sampling targets' box masses (sampler/targets): the test's
// own statistics and quadrature first, then every target's mass against
// numerical integration of its density, over the whole square and additively
// across splits.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "sampler/point.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/target.h"
#include "sampler/targets/target_spec.h"
#include "tests/common/chi_square.h"
#include "tests/sampler/target_oracles.h"

namespace nuld {
namespace {

using test::allCases;
using test::Case;
using test::chiSquare;
using test::kPi;
using test::regularizedGammaQ;

// ------------------------------------------------------------------ statistics

// P(Poisson(x) < n) = Q(n, x) for integer n, summed in log space.
double poissonBelow(int n, double x) {
  double s = 0;
  for (int k = 0; k < n; ++k) s += std::exp(-x + k * std::log(x) - std::lgamma(k + 1.0));
  return s;
}

// ------------------------------------------------------------------ quadrature

// Gauss-Kronrod 7-15 (QUADPACK qk15) on [-1, 1].
constexpr double kGkNodes[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.0};
constexpr double kKronrodWeights[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
constexpr double kGaussWeights[4] = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

using Fn1 = std::function<double(double)>;

// Adaptive bisection with a local error test |K15 - G7| <= tol, at least 4
// subintervals per piece. A jump inside an interval is bisected down to ~1e-14
// of the interval, leaving an error below 1e-13 times the jump. A jump lying
// between a piece's end and its outermost node (0.4% of its length) can go
// unseen, as with any rule that samples finitely many points: the targets'
// known jumps are therefore passed as break points.
double adaptiveGk(const Fn1 &f, double a, double b, double tol, int depth = 0) {
  const double c = 0.5 * (a + b), h = 0.5 * (b - a);
  const double fc = f(c);
  double k = fc * kKronrodWeights[7], g = fc * kGaussWeights[3];
  for (int j = 0; j < 7; ++j) {
    const double f1 = f(c - h * kGkNodes[j]), f2 = f(c + h * kGkNodes[j]);
    k += kKronrodWeights[j] * (f1 + f2);
    if (j % 2 == 1) g += kGaussWeights[j / 2] * (f1 + f2);
  }
  k *= h;
  g *= h;
  const double err = std::abs(k - g);
  if ((depth >= 2 && err <= std::max(tol, 1e-15 * std::abs(k))) || depth >= 46) return k;
  return adaptiveGk(f, a, c, 0.5 * tol, depth + 1) + adaptiveGk(f, c, b, 0.5 * tol, depth + 1);
}

// Integral over [a, b] split at the given break points (where f may jump).
double integrate1(const Fn1 &f, double a, double b, std::vector<double> breaks, double tol) {
  if (!(b > a)) return 0;
  breaks.push_back(a);
  breaks.push_back(b);
  std::sort(breaks.begin(), breaks.end());
  double sum = 0;
  for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
    const double lo = std::max(a, breaks[k]), hi = std::min(b, breaks[k + 1]);
    if (hi > lo) sum += adaptiveGk(f, lo, hi, tol * (hi - lo) / (b - a));
  }
  return sum;
}

// Numerical integral of the target's pdf over the box (zero outside [0,1]^2
// by the pdf's own definition: the box is not clipped here).
double integratePdf(const Case &c, const Box2 &box) {
  if (!(box.hi.x > box.lo.x && box.hi.y > box.lo.y)) return 0;
  std::vector<double> xb = c.xBreaks, yb = c.yBreaks;
  for (double e : {0.0, 1.0}) {
    xb.push_back(e);
    yb.push_back(e);
  }
  const Target &t = *c.target;
  auto column = [&](double x) {
    std::vector<double> breaks = yb;
    if (c.yCurve && x >= 0 && x <= 1) breaks.push_back(c.yCurve(x));
    return integrate1([&](double y) { return t.pdf({x, y}); }, box.lo.y, box.hi.y, breaks, 1e-15);
  };
  return integrate1(column, box.lo.x, box.hi.x, xb, 1e-13);
}

// ------------------------------------------------------------------ test boxes

std::string str(const Box2 &b) {
  std::string s = "[";  // appended to, not "[" + ...: GCC 12 -Wrestrict false positive
  s += std::to_string(b.lo.x) + ", " + std::to_string(b.hi.x) + "] x [" + std::to_string(b.lo.y) +
       ", " + std::to_string(b.hi.y) + "]";
  return s;
}

std::vector<Box2> testBoxes(const Case &c, std::uint64_t seed) {
  std::vector<Box2> boxes = {
      {{-1, -0.5}, {2, 3}},          // contains the square
      {{0.3, 0.1}, {0.3, 0.9}},      // zero width
      {{0.1, 0.6}, {0.8, 0.6}},      // zero height
      {{0.5, 0.5}, {0.5, 0.5}},      // a point
      {{0.7, 0.2}, {0.3, 0.9}},      // lo.x > hi.x: empty
      {{1.1, 0.2}, {1.5, 0.9}},      // right of the square
      {{-0.5, -0.5}, {0, 1}},        // touches the square's left edge
      {{0.2, 1.0}, {0.6, 1.4}},      // touches the top edge
      {{-0.3, 0.2}, {0.4, 1.3}},     // straddles two sides
      {{0, 0}, {1, 0.5}},            // lower half
      {{0, 0}, {0.5, 1}},            // left half
      {{0.99, 0.99}, {1.5, 1.5}},    // the top-right corner
      {{-0.2, -0.2}, {0.01, 0.01}},  // the bottom-left corner
  };
  Rng rng(seed);
  auto in = [&](double lo, double hi) { return lo + (hi - lo) * rng.uniform(); };
  for (int k = 0; k < 40; ++k) {  // large boxes, often partly outside
    double x0 = in(-0.25, 1.25), x1 = in(-0.25, 1.25), y0 = in(-0.25, 1.25), y1 = in(-0.25, 1.25);
    boxes.push_back({{std::min(x0, x1), std::min(y0, y1)}, {std::max(x0, x1), std::max(y0, y1)}});
  }
  for (int k = 0; k < 20; ++k) {  // small boxes
    const double cx = in(-0.02, 1.02), cy = in(-0.02, 1.02), w = in(0, 0.04), h = in(0, 0.04);
    boxes.push_back({{cx - w, cy - h}, {cx + w, cy + h}});
  }
  std::vector<double> xs = c.xBreaks, ys = c.yBreaks;
  xs.insert(xs.end(), {0.0, 1.0});
  ys.insert(ys.end(), {0.0, 1.0});
  for (int k = 0; k < 10; ++k) {  // edges on the density's jumps
    const double x0 = xs[rng.uniformInt(std::uint32_t(xs.size()))], x1 = in(-0.1, 1.1);
    const double y0 = ys[rng.uniformInt(std::uint32_t(ys.size()))],
                 y1 = ys[rng.uniformInt(std::uint32_t(ys.size()))];
    boxes.push_back({{std::min(x0, x1), std::min(y0, y1)}, {std::max(x0, x1), std::max(y0, y1)}});
  }
  for (int k = 0; k < 5; ++k) {  // degenerate boxes at random places
    const double x = in(-0.1, 1.1), y = in(-0.1, 1.1), l = in(0, 0.5);
    boxes.push_back(k % 2 ? Box2{{x, y}, {x, y + l}} : Box2{{x, y}, {x + l, y}});
  }
  return boxes;
}

// ------------------------------------------------------------ helper self-tests

TEST(TargetStats, IncompleteGammaMatchesClosedForms) {
  for (double x : {0.01, 0.5, 1.9, 3.0, 40.0}) {
    EXPECT_NEAR(regularizedGammaQ(1, x), std::exp(-x), 1e-14 * std::exp(-x)) << x;
    EXPECT_NEAR(regularizedGammaQ(0.5, x), std::erfc(std::sqrt(x)), 1e-13 * std::erfc(std::sqrt(x)))
        << x;
  }
  const std::vector<std::pair<int, double>> points = {
      {10, 7.0}, {10, 14.0}, {500, 480.0}, {500, 520.0}, {512, 600.0}};
  for (auto [n, x] : points) {
    const double expected = poissonBelow(n, x);
    EXPECT_NEAR(regularizedGammaQ(n, x), expected, 1e-10 * expected) << n << " " << x;
  }
  EXPECT_EQ(regularizedGammaQ(3, 0), 1.0);
}

TEST(TargetStats, QuadratureIsAccurate) {
  // The indicator of the unit disc with its boundary as the hint: pi / 4.
  const std::function<double(double)> curve = [](double x) { return std::sqrt(1 - x * x); };
  auto column = [&](double x) {
    return integrate1([x](double y) { return x * x + y * y <= 1 ? 1.0 : 0.0; }, 0, 1, {curve(x)},
                      1e-15);
  };
  EXPECT_NEAR(integrate1(column, 0, 1, {}, 1e-13), kPi / 4, 1e-12);
  // Jumps without hints are found when not right at the end of a piece.
  for (double jump : {0.3, 0.123456789, 0.77, 0.9})
    EXPECT_NEAR(integrate1([jump](double y) { return y < jump ? 2.0 + y : 0.5; }, 0, 1, {}, 1e-14),
                2 * jump + 0.5 * jump * jump + 0.5 * (1 - jump), 1e-13)
        << jump;
  // Smooth integrands: erf, and a narrow Gaussian.
  EXPECT_NEAR(
      integrate1([](double t) { return 2 / std::sqrt(kPi) * std::exp(-t * t); }, 0, 1.7, {}, 1e-14),
      std::erf(1.7), 1e-13);
  EXPECT_NEAR(integrate1([](double t) { return std::exp(-0.5 * t * t / 1e-4); }, -1, 2, {}, 1e-14),
              0.01 * std::sqrt(2 * kPi), 1e-13);
}

TEST(TargetStats, ChiSquareRejectsAWrongDistribution) {
  // Points of one target against another's masses must fail clearly; this is
  // what gives the chi-square test below its power.
  const auto uniform = makeTarget("uniform");
  const auto bilinear = makeTarget("bilinear:1,2,0.5,3");
  EXPECT_LT(chiSquare(*uniform, *bilinear, 200000, 32, 7).pValue, 1e-6);
  const auto g1 = makeTarget("gaussian:0.3,0.6,0.15");
  const auto g2 = makeTarget("gaussian:0.3,0.6,0.16");
  EXPECT_LT(chiSquare(*g1, *g2, 200000, 32, 7).pValue, 1e-6);
}

// ------------------------------------------------------------------ 1. mass

TEST(TargetMass, WholeSquareIsOne) {
  for (const Case &c : allCases()) {
    EXPECT_NEAR(c.target->mass({{0, 0}, {1, 1}}), 1.0, 1e-12) << c.name;
    EXPECT_NEAR(c.target->mass({{-3, -2}, {5, 4}}), 1.0, 1e-12) << c.name;
  }
}

TEST(TargetMass, AgreesWithQuadratureOfPdf) {
  // The quadrature is adaptive Gauss-Kronrod, split at the density's jumps,
  // asked for 1e-13 absolute (its error estimates are conservative); the
  // closed forms are exact up to rounding.
  constexpr double kTol = 1e-12;
  std::uint64_t seed = 100;
  for (const Case &c : allCases()) {
    SCOPED_TRACE(c.name);
    double worst = -1, worstMass = 0, worstQuad = 0;
    Box2 worstBox;
    for (const Box2 &box : testBoxes(c, seed++)) {
      const double m = c.target->mass(box), q = integratePdf(c, box);
      EXPECT_TRUE(std::isfinite(m)) << str(box);
      EXPECT_GE(m, 0.0) << str(box);
      if (box.clipped().area() == 0) {
        EXPECT_EQ(m, 0.0) << "zero-area box " << str(box);
      }
      const double err = std::abs(m - q);
      if (err > worst) {
        worst = err;
        worstBox = box;
        worstMass = m;
        worstQuad = q;
      }
    }
    EXPECT_LE(worst, kTol) << "box " << str(worstBox) << ": mass " << worstMass << ", quadrature "
                           << worstQuad;
  }
}

TEST(TargetMass, IsAdditiveAcrossSplits) {
  // mass(A) = mass(left part) + mass(right part), split at random x and y.
  Rng rng(5);
  for (const Case &c : allCases()) {
    double worst = 0;
    for (int k = 0; k < 200; ++k) {
      const double x0 = rng.uniform() * 1.2 - 0.1, x1 = rng.uniform() * 1.2 - 0.1;
      const double y0 = rng.uniform() * 1.2 - 0.1, y1 = rng.uniform() * 1.2 - 0.1;
      const Box2 b{{std::min(x0, x1), std::min(y0, y1)}, {std::max(x0, x1), std::max(y0, y1)}};
      const double sx = b.lo.x + (b.hi.x - b.lo.x) * rng.uniform();
      const double sy = b.lo.y + (b.hi.y - b.lo.y) * rng.uniform();
      const double whole = c.target->mass(b);
      const double parts =
          c.target->mass({b.lo, {sx, sy}}) + c.target->mass({{sx, b.lo.y}, {b.hi.x, sy}}) +
          c.target->mass({{b.lo.x, sy}, {sx, b.hi.y}}) + c.target->mass({{sx, sy}, b.hi});
      worst = std::max(worst, std::abs(whole - parts));
    }
    EXPECT_LE(worst, 1e-13) << c.name;
  }
}

}  // namespace
}  // namespace nuld
