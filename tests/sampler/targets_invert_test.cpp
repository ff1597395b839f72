// Tests of the sampling targets' inverse-CDF maps (sampler/targets): the
// mapped points against the box masses by a chi-square test, the map as the
// Rosenblatt transform of the masses, and its Jacobian against finite
// differences and the density.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "sampler/point.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/grid_target.h"
#include "sampler/targets/target.h"
#include "sampler/targets/target_spec.h"
#include "tests/sampler/target_oracles.h"

namespace nuld {
namespace {

using test::allCases;
using test::Case;
using test::chiSquare;
using ChiSquare = test::MassChiSquare;

// ------------------------------------------------------------------ 2. invert

TEST(TargetInvert, ChiSquareAgainstMass) {
  const auto &cases = allCases();
  // Sidak correction: overall false-alarm rate 1% across the targets.
  const double alpha = 1 - std::pow(0.99, 1.0 / double(cases.size()));
  std::uint64_t seed = 1000;
  for (const Case &c : cases) {
    const ChiSquare r = chiSquare(*c.target, *c.target, 200000, 32, seed++);
    EXPECT_NEAR(r.totalMass, 1.0, 1e-12) << c.name;
    EXPECT_EQ(r.outside, 0u) << c.name << ": mapped points outside [0,1]^2";
    EXPECT_EQ(r.zeroDensity, 0u) << c.name << ": mapped points where pdf = 0";
    EXPECT_EQ(r.inEmptyCells, 0u) << c.name << ": mapped points in zero-mass cells";
    EXPECT_GT(r.pValue, alpha) << c.name << ": chi^2 = " << r.statistic << " with " << r.dof
                               << " degrees of freedom";
  }
}

// The box with coordinate `axis` in [lo, hi] and the other in [lo2, hi2].
Box2 slab(int axis, double lo, double hi, double lo2 = 0, double hi2 = 1) {
  return axis == 0 ? Box2{{lo, lo2}, {hi, hi2}} : Box2{{lo2, lo}, {hi2, hi}};
}

TEST(TargetInvert, IsTheRosenblattTransform) {
  // The first coordinate inverts the marginal CDF, the second the conditional
  // CDF given the first; both CDFs are read from `mass` (the conditional one
  // over a slab of half-width 1e-6, an O(1e-12) approximation that loses
  // ~1e-10 to rounding).
  constexpr double kDelta = 1e-6;
  std::uint64_t seed = 1500;
  for (const Case &c : allCases()) {
    const Target &t = *c.target;
    const int a = c.firstAxis, b = 1 - a;
    Rng rng(seed++);
    double worstMarginal = 0, worstConditional = 0;
    Point2 worstMarginalU, worstConditionalU;
    int conditionals = 0;
    for (int k = 0; k < 2000; ++k) {
      const Point2 u{rng.uniform(), rng.uniform()};
      const Point2 x = t.invert(u).x;
      const double marginal = t.mass(slab(a, 0, x[a]));
      if (!(std::abs(marginal - u[a]) <= worstMarginal)) {
        worstMarginal = std::abs(marginal - u[a]);
        worstMarginalU = u;
      }
      // The slab must lie inside the square and one smooth piece.
      const double lo = x[a] - kDelta, hi = x[a] + kDelta;
      Point2 pLo = x, pHi = x;
      pLo[a] = lo;
      pHi[a] = hi;
      if (lo < 0 || hi > 1 || c.region(pLo) != c.region(pHi)) continue;
      const double slabMass = t.mass(slab(a, lo, hi));
      if (!(slabMass > 1e-9)) continue;  // too little mass to divide by
      ++conditionals;
      const double conditional = t.mass(slab(a, lo, hi, 0, x[b])) / slabMass;
      if (!(std::abs(conditional - u[b]) <= worstConditional)) {
        worstConditional = std::abs(conditional - u[b]);
        worstConditionalU = u;
      }
    }
    EXPECT_LE(worstMarginal, 1e-12)
        << c.name << " at u = (" << worstMarginalU.x << ", " << worstMarginalU.y << ")";
    EXPECT_LE(worstConditional, 1e-7)
        << c.name << " at u = (" << worstConditionalU.x << ", " << worstConditionalU.y << ")";
    EXPECT_GE(conditionals, 1900) << c.name;
  }
}

// Regression: for a broad Gaussian the computed CDF is flat over runs of many
// ulps; Newton used to stall there and return the midpoint of a bracket that
// never shrank (gaussian:0.5,0.5,100 sent u.x = 0.5004 to x = 0.7502).
TEST(TargetInvert, BroadGaussianInvertsItsCdf) {
  for (const char *spec :
       {"gaussian:0.5,0.5,20", "gaussian:0.5,0.5,100", "gaussian:0.3,0.6,1000"}) {
    const auto t = makeTarget(spec);
    Rng rng(77);
    int bad = 0;
    double worst = 0;
    Point2 worstU;
    for (int k = 0; k < 100000; ++k) {
      const Point2 u{rng.uniform(), rng.uniform()};
      const Point2 x = t->invert(u).x;
      const double err = std::max(std::abs(t->mass({{0, 0}, {x.x, 1}}) - u.x),
                                  std::abs(t->mass({{0, 0}, {1, x.y}}) - u.y));
      if (err > 1e-9) ++bad;
      if (err > worst) {
        worst = err;
        worstU = u;
      }
    }
    EXPECT_EQ(bad, 0) << spec << ": worst CDF error " << worst << " at u = (" << worstU.x << ", "
                      << worstU.y << ")";
  }
  const auto g = makeTarget("gaussian:0.5,0.5,20");
  EXPECT_NEAR(g->mass({{0, 0}, {g->invert({0.093653035755318026, 0.5}).x.x, 1}}),
              0.093653035755318026, 1e-12);
}

// ------------------------------------------------------------------ 3. Jacobian

TEST(TargetJacobian, MatchesFiniteDifferences) {
  constexpr double kStep = 1e-6, kTol = 1e-4;
  std::uint64_t seed = 2000;
  for (const Case &c : allCases()) {
    SCOPED_TRACE(c.name);
    const Target &t = *c.target;
    Rng rng(seed++);
    int tested = 0, skipped = 0;
    double worst = 0;
    std::string worstWhere;
    for (int k = 0; k < 500; ++k) {
      const Point2 u{0.001 + 0.998 * rng.uniform(), 0.001 + 0.998 * rng.uniform()};
      const Inversion inv = t.invert(u);
      const int piece = c.region(inv.x);
      double fd[2][2];
      bool crosses = false;
      for (int col = 0; col < 2; ++col) {
        Point2 up = u, dn = u;
        up[col] += kStep;
        dn[col] -= kStep;
        const Point2 xp = t.invert(up).x, xm = t.invert(dn).x;
        crosses = crosses || c.region(xp) != piece || c.region(xm) != piece;
        for (int row = 0; row < 2; ++row) fd[row][col] = (xp[row] - xm[row]) / (2 * kStep);
      }
      if (crosses) {  // a cell or kink boundary within the step
        ++skipped;
        continue;
      }
      ++tested;
      for (int row = 0; row < 2; ++row) {
        const auto &J = inv.jacobian.m;
        const double scale = std::max(std::abs(J[row][0]), std::abs(J[row][1]));
        for (int col = 0; col < 2; ++col) {
          const double err = std::abs(fd[row][col] - J[row][col]) / scale;
          if (!(err <= worst)) {
            worst = err;
            worstWhere = "u = (" + std::to_string(u.x) + ", " + std::to_string(u.y) + "), J[" +
                         std::to_string(row) + "][" + std::to_string(col) +
                         "] = " + std::to_string(J[row][col]) + ", finite difference " +
                         std::to_string(fd[row][col]);
          }
        }
      }
    }
    EXPECT_LE(worst, kTol) << worstWhere;
    EXPECT_GE(tested, 475) << "skipped " << skipped;
  }
}

TEST(TargetJacobian, DeterminantTimesPdfIsOne) {
  std::uint64_t seed = 3000;
  for (const Case &c : allCases()) {
    const Target &t = *c.target;
    Rng rng(seed++);
    double worst = 0;
    Point2 worstU;
    int zeroPdf = 0;
    for (int k = 0; k < 2000; ++k) {
      const Point2 u{rng.uniform(), rng.uniform()};
      const Inversion inv = t.invert(u);
      const double p = t.pdf(inv.x);
      if (!(p > 0)) {
        ++zeroPdf;
        continue;
      }
      const double err = std::abs(std::abs(inv.jacobian.determinant()) * p - 1);
      if (!(err <= worst)) {
        worst = err;
        worstU = u;
      }
    }
    EXPECT_LE(worst, 1e-6) << c.name << " at u = (" << worstU.x << ", " << worstU.y << ")";
    EXPECT_EQ(zeroPdf, 0) << c.name;
  }
}

}  // namespace
}  // namespace nuld

namespace nuld {
namespace {

// Uneven cells, zero-density cells and a zero-density row.
GridTarget unevenGrid() {
  const std::vector<double> xs{0, 0.1, 0.5, 0.55, 1}, ys{0, 0.3, 0.5, 1};
  const std::vector<double> density{1, 0, 3, 0.5,  // row 0
                                    2, 7, 0, 1,    // row 1
                                    0, 0, 0, 0};   // row 2: none
  return GridTarget(xs, ys, density, "test-grid", Domain::Square, "test");
}

// GridTarget::primaryOf is the inverse of invert(): u -> x -> u round-trips
// for every u, and so x -> u -> x for every x that invert() makes, on a
// grid of uneven cells with zero-density cells and a zero-density row.
TEST(TargetInvert, PrimaryOfInvertsTheGridMap) {
  const GridTarget grid = unevenGrid();
  Rng rng(4);
  for (int k = 0; k < 20000; ++k) {
    const Point2 u{rng.uniform(), rng.uniform()};
    const Point2 x = grid.invert(u).x;
    const Point2 back = grid.primaryOf(x);
    ASSERT_NEAR(back.x, u.x, 1e-12);
    ASSERT_NEAR(back.y, u.y, 1e-12);
    EXPECT_GT(grid.pdf(x), 0);
  }
}

// GridTarget::draw gives invert()'s point, the cell that holds it, and that
// cell's density (from the inversion's masses, not the density table), on
// the same uneven grid; u at the square's edges included.
TEST(TargetInvert, DrawGivesThePointItsCellAndTheCellsDensity) {
  const GridTarget grid = unevenGrid();
  const std::vector<double> &xs = grid.xEdges(), &ys = grid.yEdges();
  Rng rng(5);
  std::vector<Point2> us{{0, 0}, {1, 1}, {0, 1}, {1, 0}};
  for (int k = 0; k < 20000; ++k) us.push_back({rng.uniform(), rng.uniform()});
  for (const Point2 u : us) {
    const GridTarget::Draw d = grid.draw(u);
    const Point2 x = grid.invert(u).x;
    ASSERT_EQ(d.x.x, x.x);
    ASSERT_EQ(d.x.y, x.y);
    ASSERT_GE(d.cell.i, 0);
    ASSERT_GE(d.cell.j, 0);
    const double expected = grid.cellDensity(d.cell.i, d.cell.j);
    ASSERT_GT(expected, 0) << u.x << " " << u.y;
    ASSERT_NEAR(d.density, expected, 1e-12 * expected) << u.x << " " << u.y;
    // The point lies in its cell (on its edge at most).
    ASSERT_GE(x.x, xs[d.cell.i]);
    ASSERT_LE(x.x, xs[d.cell.i + 1]);
    ASSERT_GE(x.y, ys[d.cell.j]);
    ASSERT_LE(x.y, ys[d.cell.j + 1]);
  }
}

}  // namespace
}  // namespace nuld
