// Tests of the sampling targets (sampler/targets): box masses against
// numerical integration of the density, the inverse-CDF map against the
// density by a chi-square test, the map's Jacobian against finite
// differences, bad input and the environment-map parameterization.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "sampler/io/image_io.h"
#include "sampler/point.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/grid_target.h"
#include "sampler/targets/image_targets.h"
#include "sampler/targets/target.h"
#include "sampler/targets/target_spec.h"
#include "tests/common/chi_square.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;

// ------------------------------------------------------------------ statistics

using test::regularizedGammaQ;

// P(Poisson(x) < n) = Q(n, x) for integer n, summed in log space.
double poissonBelow(int n, double x) {
  double s = 0;
  for (int k = 0; k < n; ++k) s += std::exp(-x + k * std::log(x) - std::lgamma(k + 1.0));
  return s;
}

struct ChiSquare {
  double statistic = 0;
  int dof = 0;
  double pValue = 0;
  std::size_t outside = 0;       // mapped points outside [0,1]^2 (or not finite)
  std::size_t zeroDensity = 0;   // mapped points where the sampled target's pdf is 0
  std::size_t inEmptyCells = 0;  // points in cells the reference gives no mass
  double totalMass = 0;          // sum of the reference's cell masses
};

// Maps n uniform points through `sampled.invert`, bins them into bins x bins
// cells and compares with the cell masses of `reference` (pbrt-v4 / Mitsuba
// style: cells expected to hold fewer than 5 points are pooled).
ChiSquare chiSquare(const Target &sampled, const Target &reference, int n, int bins,
                    std::uint64_t seed) {
  ChiSquare r;
  std::vector<double> observed(std::size_t(bins) * bins, 0.0);
  Rng rng(seed);
  for (int k = 0; k < n; ++k) {
    const double ux = rng.uniform();
    const double uy = rng.uniform();
    const Point2 x = sampled.invert({ux, uy}).x;
    if (!isFinite(x) || x.x < 0 || x.x > 1 || x.y < 0 || x.y > 1) {
      ++r.outside;
      continue;
    }
    if (!(sampled.pdf(x) > 0)) ++r.zeroDensity;
    const int i = std::min(int(x.x * bins), bins - 1), j = std::min(int(x.y * bins), bins - 1);
    observed[std::size_t(j) * bins + i] += 1;
  }
  std::vector<std::pair<double, double>> cells;  // (expected, observed)
  for (int j = 0; j < bins; ++j)
    for (int i = 0; i < bins; ++i) {
      const Box2 cell{{double(i) / bins, double(j) / bins},
                      {double(i + 1) / bins, double(j + 1) / bins}};
      const double m = reference.mass(cell);
      r.totalMass += m;
      cells.push_back({m * n, observed[std::size_t(j) * bins + i]});
    }
  std::sort(cells.begin(), cells.end());
  double pooledExpected = 0, pooledObserved = 0;
  std::vector<std::pair<double, double>> kept;
  for (const auto &[e, o] : cells) {
    if (e <= 0 && o > 0) r.inEmptyCells += std::size_t(o);
    if (e < 5) {
      pooledExpected += e;
      pooledObserved += o;
    } else {
      kept.push_back({e, o});
    }
  }
  if (pooledExpected > 0) {
    if (pooledExpected < 5 && !kept.empty()) {
      kept.front().first += pooledExpected;  // the smallest cell left
      kept.front().second += pooledObserved;
    } else {
      kept.push_back({pooledExpected, pooledObserved});
    }
  }
  for (const auto &[e, o] : kept) r.statistic += (o - e) * (o - e) / e;
  r.dof = int(kept.size()) - 1;
  r.pValue = r.dof > 0 ? regularizedGammaQ(0.5 * r.dof, 0.5 * r.statistic) : 1.0;
  if (r.inEmptyCells > 0) r.pValue = 0;
  return r;
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

// --------------------------------------------------------------- the targets

struct Case {
  std::string name;
  std::shared_ptr<const Target> target;
  // Where the density may jump: lines x = const, y = const, and a curve
  // y = yCurve(x). Only hints for the quadrature, which is adaptive anyway.
  std::vector<double> xBreaks, yBreaks;
  std::function<double(double)> yCurve;
  // Id of the smooth piece of the inverse map containing a mapped point.
  std::function<int(Point2)> region = [](Point2) { return 0; };
  // The axis the inverse map samples first from its marginal (the grid
  // samples a row, then a column in it; the closed forms x, then y given x).
  int firstAxis = 0;
};

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

Case closedFormCase(std::string name, const std::string &spec) {
  Case c;
  c.name = std::move(name);
  c.target = makeTarget(spec);
  return c;
}

int cellOf(const std::vector<double> &edges, double t) {
  return int(std::upper_bound(edges.begin(), edges.end(), t) - edges.begin());
}

Case gridCase(std::string name, std::shared_ptr<const Target> target, std::vector<double> xEdges,
              std::vector<double> yEdges) {
  Case c;
  c.name = std::move(name);
  c.target = std::move(target);
  c.xBreaks = xEdges;
  c.yBreaks = yEdges;
  c.region = [xEdges, yEdges](Point2 p) {
    return cellOf(xEdges, p.x) * 1000 + cellOf(yEdges, p.y);
  };
  c.firstAxis = 1;
  return c;
}

std::vector<double> uniformEdges(int cells) {
  std::vector<double> e(cells + 1);
  for (int i = 0; i <= cells; ++i) e[i] = double(i) / cells;
  return e;
}

// Equal-area v of the lat-long rows' edges: v = (1 - cos theta) / 2.
std::vector<double> envmapRowEdges(int rows) {
  std::vector<double> e(rows + 1);
  for (int j = 0; j <= rows; ++j) e[j] = 0.5 * (1 - std::cos(kPi * j / rows));
  e.front() = 0;
  e.back() = 1;
  return e;
}

// Uneven edges, a zero row in the middle, zero cells.
const std::vector<double> kGridAx = {0, 0.1, 0.35, 0.4, 0.8, 1};
const std::vector<double> kGridAy = {0, 0.2, 0.25, 0.7, 1};
const std::vector<double> kGridAd = {1, 3, 0, 2, 0.5,  //
                                     0, 0, 0, 0, 0,    //
                                     4, 0, 7, 1, 2,    //
                                     0, 2, 2, 0, 9};
// Zero first and last rows, zero first column in some rows.
const std::vector<double> kGridBx = {0, 0.3, 0.5, 1};
const std::vector<double> kGridBy = {0, 0.15, 0.6, 0.65, 1};
const std::vector<double> kGridBd = {0, 0, 0,  //
                                     0, 5, 1,  //
                                     2, 0, 3,  //
                                     0, 0, 0};

// A small lat-long environment map (RGB, 8 x 6) with a bright zenith pixel
// and some black pixels.
Image envmapImage() {
  Image img;
  img.width = 8;
  img.height = 6;
  img.channels = 3;
  img.pixels.assign(std::size_t(img.width) * img.height * img.channels, 0.0f);
  for (int j = 0; j < img.height; ++j)
    for (int i = 0; i < img.width; ++i) {
      img.at(i, j, 0) = float(0.1 + ((3 * i + 5 * j) % 7) * 0.3);
      img.at(i, j, 1) = float(0.2 + ((i + 2 * j) % 5) * 0.25);
      img.at(i, j, 2) = float(0.05 + ((7 * i + j) % 4) * 0.5);
    }
  for (int i = 2; i <= 5; ++i)
    for (int ch = 0; ch < 3; ++ch) img.at(i, 4, ch) = 0.0f;
  for (int ch = 0; ch < 3; ++ch) img.at(0, 0, ch) = 20.0f;
  return img;
}

// A small grey picture (5 x 3) with black pixels.
Image pictureImage() {
  const float values[3][5] = {{1, 2, 0, 4, 1}, {0, 0, 3, 1, 2}, {5, 1, 1, 0, 2}};
  Image img;
  img.width = 5;
  img.height = 3;
  img.channels = 1;
  img.pixels.resize(15);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 5; ++i) img.at(i, j, 0) = values[j][i];
  return img;
}

// Rec. 709 luminance, written out independently of Image::luminance.
double luminance709(const Image &img, int i, int j) {
  if (img.channels < 3) return img.at(i, j, 0);
  return 0.2126 * img.at(i, j, 0) + 0.7152 * img.at(i, j, 1) + 0.0722 * img.at(i, j, 2);
}

const std::vector<Case> &allCases() {
  static const std::vector<Case> cases = [] {
    std::vector<Case> v;
    v.push_back(closedFormCase("uniform", "uniform"));
    v.push_back(closedFormCase("bilinear", "bilinear:1,2,0.5,3"));
    v.push_back(closedFormCase("bilinear-zero-corner", "bilinear:0,1,1,2"));
    v.push_back(closedFormCase("gaussian", "gaussian:0.3,0.6,0.15"));
    v.push_back(closedFormCase("gaussian-mean-outside", "gaussian:-0.2,0.5,0.1"));
    Case disc = closedFormCase("quarterdisc", "quarterdisc");
    disc.yCurve = [](double x) { return std::sqrt(std::max(0.0, 1 - x * x)); };
    v.push_back(disc);
    Case step = closedFormCase("step", "step:0.4,1,3");
    step.xBreaks = {0.4};
    step.region = [](Point2 p) { return p.x < 0.4 ? 0 : 1; };
    v.push_back(step);
    Case halfStep = closedFormCase("step-default-weights", "step:0.5");
    halfStep.xBreaks = {0.5};
    halfStep.region = [](Point2 p) { return p.x < 0.5 ? 0 : 1; };
    v.push_back(halfStep);
    v.push_back(gridCase(
        "grid-a",
        std::make_shared<GridTarget>(kGridAx, kGridAy, kGridAd, "grid-a", Domain::Square, "grid-a"),
        kGridAx, kGridAy));
    v.push_back(gridCase(
        "grid-b",
        std::make_shared<GridTarget>(kGridBx, kGridBy, kGridBd, "grid-b", Domain::Square, "grid-b"),
        kGridBx, kGridBy));
    const Image env = envmapImage();
    v.push_back(gridCase("envmap", makeEnvmapTarget(env, "memory-envmap"), uniformEdges(env.width),
                         envmapRowEdges(env.height)));
    const Image pic = pictureImage();
    v.push_back(gridCase("image", makeImageTarget(pic, "memory-picture"), uniformEdges(pic.width),
                         uniformEdges(pic.height)));
    return v;
  }();
  return cases;
}

std::string str(const Box2 &b) {
  return "[" + std::to_string(b.lo.x) + ", " + std::to_string(b.hi.x) + "] x [" +
         std::to_string(b.lo.y) + ", " + std::to_string(b.hi.y) + "]";
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

// ------------------------------------------------------------ 4. stability, input

TEST(TargetInput, InvertIsFiniteAtTheEdges) {
  const double below1 = std::nextafter(1.0, 0.0);
  const std::vector<Point2> us = {{0, 0},
                                  {1, 1},
                                  {0, 1},
                                  {1, 0},
                                  {0.999999999999, 0},
                                  {0, 0.999999999999},
                                  {below1, below1},
                                  {0.5, 0},
                                  {0.5, 1},
                                  {0, 0.5},
                                  {1, 0.5},
                                  {1e-300, 1e-300},
                                  {std::numeric_limits<double>::denorm_min(), 0.5},
                                  {1e-16, 1 - 1e-16}};
  std::vector<std::shared_ptr<const Target>> targets;
  for (const Case &c : allCases()) targets.push_back(c.target);
  for (const char *s :
       {"bilinear:0,1,0,1", "bilinear:0,0,0,1", "bilinear:1,0,0,0", "step:0,1,2", "step:1,1,0",
        "step:0.999,0,1", "gaussian:0.5,0.5,0.001", "gaussian:-1,0.5,0.2", "gaussian:1.5,-0.5,0.1"})
    targets.push_back(makeTarget(s));
  for (const auto &t : targets)
    for (const Point2 u : us) {
      const Inversion inv = t->invert(u);
      const std::string where =
          t->spec() + " at u = (" + std::to_string(u.x) + ", " + std::to_string(u.y) + ")";
      EXPECT_TRUE(isFinite(inv.x)) << where;
      EXPECT_TRUE(inv.x.x >= 0 && inv.x.x <= 1 && inv.x.y >= 0 && inv.x.y <= 1)
          << where << ": x = (" << inv.x.x << ", " << inv.x.y << ")";
      for (int r = 0; r < 2; ++r)
        for (int col = 0; col < 2; ++col)
          EXPECT_TRUE(std::isfinite(inv.jacobian.m[r][col]))
              << where << ": J[" << r << "][" << col << "] = " << inv.jacobian.m[r][col];
    }
}

// The message of the exception of type E that f throws, or a note saying
// what happened instead.
template <typename E, typename F>
std::string messageOf(F &&f) {
  try {
    f();
  } catch (const std::exception &e) {
    if constexpr (!std::is_same_v<E, std::exception>)
      if (!dynamic_cast<const E *>(&e))
        return std::string("<wrong exception type: ") + e.what() + ">";
    return e.what();
  }
  return "<no exception>";
}

bool contains(const std::string &s, const std::string &part) {
  return s.find(part) != std::string::npos;
}

TEST(TargetInput, GridRejectsBadDensities) {
  const auto e = uniformEdges(2);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::vector<double>> bad = {
      {0, 0, 0, 0}, {1, nan, 1, 1}, {1, 1, -0.5, 1}, {inf, 1, 1, 1}, {nan, nan, nan, nan}};
  for (const auto &d : bad) {
    const std::string msg = messageOf<std::invalid_argument>(
        [&] { GridTarget(e, e, d, "grid", Domain::Square, "densities-from-test.bin"); });
    EXPECT_TRUE(contains(msg, "densities-from-test.bin")) << msg;
  }
  // Wrong counts and bad edges are rejected too.
  EXPECT_THROW(GridTarget(e, e, {1, 1, 1}, "grid", Domain::Square, "src"), std::invalid_argument);
  EXPECT_THROW(GridTarget({0, 0.5, 0.5, 1}, e, {1, 1, 1, 1, 1, 1}, "grid", Domain::Square, "src"),
               std::invalid_argument);
  EXPECT_THROW(GridTarget({0, 0.5, 0.9}, e, {1, 1, 1, 1}, "grid", Domain::Square, "src"),
               std::invalid_argument);
  // An all-black image names its source.
  Image black = pictureImage();
  std::fill(black.pixels.begin(), black.pixels.end(), 0.0f);
  const std::string msg =
      messageOf<std::invalid_argument>([&] { makeImageTarget(black, "black-picture"); });
  EXPECT_TRUE(contains(msg, "black-picture")) << msg;
}

TEST(TargetInput, MakeTargetRejectsBadSpecs) {
  for (const char *spec : {"nosuchfamily",
                           "nosuchfamily:1,2",
                           "bilinear:1,2",
                           "bilinear:1,2,3,4,5",
                           "bilinear:",
                           "bilinear",
                           "gaussian:a,b,c",
                           "gaussian:0.5,0.5",
                           "gaussian:0.5,0.5,0",
                           "gaussian:0.5,0.5,-0.1",
                           "gaussian:0.5,0.5,nan",
                           "gaussian:0.5,0.5,1e400",
                           "gaussian:0.5,,0.1",
                           "bilinear:1,2,3,4,",
                           "bilinear:1,2,-3,4",
                           "bilinear:0,0,0,0",
                           "step:",
                           "step:1.5",
                           "step:0.5,1,2,3",
                           "step:1",
                           "step:0.5,-1,1",
                           "uniform:1",
                           "quarterdisc:2",
                           "image:",
                           "envmap:"}) {
    const std::string msg = messageOf<std::invalid_argument>([&] { makeTarget(spec); });
    EXPECT_TRUE(contains(msg, std::string("'") + spec + "'")) << spec << " -> " << msg;
  }
}

TEST(TargetInput, SpecsRoundTrip) {
  for (const char *spec : {"uniform", "quarterdisc", "bilinear:1,2,0.5,3", "gaussian:0.3,0.6,0.15",
                           "step:0.4,1,3", "step:0.5"}) {
    const auto t = makeTarget(spec);
    const auto again = makeTarget(t->spec());
    EXPECT_EQ(again->spec(), t->spec()) << spec;
    const Box2 box{{0.1, 0.2}, {0.55, 0.9}};
    EXPECT_EQ(again->mass(box), t->mass(box)) << spec;
  }
}

struct TempDir {
  std::filesystem::path path;
  TempDir() {
    path = std::filesystem::temp_directory_path() /
           ("nuld_targets_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string file(const std::string &name) const { return (path / name).string(); }
};

Image constantImage(int w, int h, float v) {
  Image img;
  img.width = w;
  img.height = h;
  img.channels = 1;
  img.pixels.assign(std::size_t(w) * h, v);
  return img;
}

TEST(TargetInput, ImageFileErrorsNameTheFile) {
  const std::string missing = "/nonexistent-nuld-dir/nonexistent.png";
  for (const std::string family : {"image:", "envmap:"}) {
    const std::string msg = messageOf<std::exception>([&] { makeTarget(family + missing); });
    EXPECT_TRUE(contains(msg, missing)) << msg;
  }

  TempDir dir;
  Image img = constantImage(4, 4, 1.0f);
  img.at(2, 1, 0) = std::numeric_limits<float>::quiet_NaN();
  const std::string nanPath = dir.file("nan-pixel.exr");
  writeImage(nanPath, img);
  for (const std::string family : {"image:", "envmap:"}) {
    const std::string msg = messageOf<std::exception>([&] { makeTarget(family + nanPath); });
    EXPECT_TRUE(contains(msg, nanPath)) << msg;
  }

  const std::string blackPath = dir.file("black.exr");
  writeImage(blackPath, constantImage(4, 4, 0.0f));
  const std::string msg = messageOf<std::exception>([&] { makeTarget("image:" + blackPath); });
  EXPECT_TRUE(contains(msg, blackPath)) << msg;
}

TEST(TargetInput, HighDynamicRangeImage) {
  // One pixel at 1e6, the other 15 at 1: the hot pixel holds 1e6 / (1e6 + 15).
  TempDir dir;
  Image img = constantImage(4, 4, 1.0f);
  const int hotX = 1, hotY = 0;  // image row 0 is the top of the picture (y = 1)
  img.at(hotX, hotY, 0) = 1e6f;
  const std::string path = dir.file("hot.exr");
  writeImage(path, img);
  const auto fromFile = makeTarget("image:" + path);
  const auto fromMemory = makeImageTarget(img, "hot");
  const double expected = 1e6 / (1e6 + 15);
  const Box2 hotCell{{0.25 * hotX, 0.75 - 0.25 * hotY}, {0.25 * (hotX + 1), 1.0 - 0.25 * hotY}};
  for (const Target *t : std::vector<const Target *>{fromFile.get(), fromMemory.get()}) {
    EXPECT_NEAR(t->mass(hotCell), expected, 1e-12 * expected) << t->spec();
    const Box2 coldCell{{0.5, 0.25}, {0.75, 0.5}};
    EXPECT_NEAR(t->mass(coldCell), 1 / (1e6 + 15), 1e-9 / (1e6 + 15)) << t->spec();
  }
  // Points that land in the hot cell: binomial, 5 standard deviations.
  const int n = 4000000;
  Rng rng(42);
  int hot = 0;
  for (int k = 0; k < n; ++k) {
    const Point2 x = fromFile->invert({rng.uniform(), rng.uniform()}).x;
    if (hotCell.contains(x)) ++hot;
  }
  const double mean = n * expected, sd = std::sqrt(n * expected * (1 - expected));
  EXPECT_NEAR(hot, mean, 5 * sd) << "expected " << n - mean << " points outside the hot cell";
  const ChiSquare r = chiSquare(*fromFile, *fromFile, 1000000, 4, 43);
  EXPECT_GT(r.pValue, 0.01) << "chi^2 = " << r.statistic << ", dof " << r.dof;
}

// ------------------------------------------------------------------ 5. envmap

TEST(TargetEnvmap, BandMassIsLuminanceWeightedSolidAngle) {
  const Image img = envmapImage();
  const int W = img.width, H = img.height;
  const auto target = makeEnvmapTarget(img, "memory-envmap");
  EXPECT_EQ(target->domain(), Domain::Sphere);
  // Independent reference: sum of L * solid angle over the lat-long pixels,
  // row j covering theta in [pi j / H, pi (j + 1) / H], theta = 0 the zenith.
  std::vector<double> weight(std::size_t(W) * H);
  double total = 0;
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) {
      const double solidAngle =
          (2 * kPi / W) * (std::cos(kPi * j / H) - std::cos(kPi * (j + 1) / H));
      weight[std::size_t(j) * W + i] = std::max(0.0, luminance709(img, i, j)) * solidAngle;
      total += weight[std::size_t(j) * W + i];
    }
  auto reference = [&](int i0, int i1, int j0, int j1) {
    double s = 0;
    for (int j = j0; j < j1; ++j)
      for (int i = i0; i < i1; ++i) s += weight[std::size_t(j) * W + i];
    return s / total;
  };
  auto v = [&](int j) { return 0.5 * (1 - std::cos(kPi * j / H)); };
  for (int j0 = 0; j0 < H; ++j0)
    for (int j1 = j0 + 1; j1 <= H; ++j1) {
      const Box2 band{{0, v(j0)}, {1, v(j1)}};
      EXPECT_NEAR(target->mass(band), reference(0, W, j0, j1), 1e-12)
          << "rows " << j0 << " to " << j1;
    }
  // The upper hemisphere is v in [0, 1/2].
  EXPECT_NEAR(target->mass({{0, 0}, {1, 0.5}}), reference(0, W, 0, H / 2), 1e-12);
  // Partial longitude ranges.
  const std::vector<std::array<int, 4>> blocks = {
      {0, 1, 0, 1}, {3, 7, 1, 4}, {2, 6, 4, 5}, {5, 8, 2, 6}};
  for (auto [i0, i1, j0, j1] : blocks) {
    const Box2 b{{double(i0) / W, v(j0)}, {double(i1) / W, v(j1)}};
    EXPECT_NEAR(target->mass(b), reference(i0, i1, j0, j1), 1e-12)
        << "columns " << i0 << "-" << i1 << ", rows " << j0 << "-" << j1;
  }
  // The same map read from a float EXR file.
  TempDir dir;
  const std::string path = dir.file("envmap.exr");
  writeImage(path, img);
  const auto fromFile = makeTarget("envmap:" + path);
  EXPECT_EQ(fromFile->domain(), Domain::Sphere);
  for (int j0 = 0; j0 < H; ++j0)
    EXPECT_NEAR(fromFile->mass({{0.1, v(j0)}, {0.8, v(H)}}),
                target->mass({{0.1, v(j0)}, {0.8, v(H)}}), 1e-15);
  // The density per unit (u, v) area is luminance per solid angle, row 0 at v
  // near 0: pdf = L / (sum L dOmega) * 4 pi.
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) {
      const Point2 center{(i + 0.5) / W, 0.5 * (v(j) + v(j + 1))};
      const double expected = std::max(0.0, luminance709(img, i, j)) / total * 4 * kPi;
      EXPECT_NEAR(target->pdf(center), expected, 1e-12 * std::max(1.0, expected))
          << "pixel " << i << ", " << j;
    }
}

}  // namespace
}  // namespace nuld
