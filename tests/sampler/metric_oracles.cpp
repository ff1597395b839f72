// The shared oracles of the metric tests: see metric_oracles.h.

#include "tests/sampler/metric_oracles.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sampler/point.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/target.h"

namespace nuld::test {

std::vector<Point2> randomPoints(std::size_t n, std::uint64_t seed) {
  TestRng rng(seed);
  std::vector<Point2> p(n);
  for (Point2 &q : p) q = {rng.uniform(), rng.uniform()};
  return p;
}

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

Box2 cornerBox(int cx, int cy, double a, double b) {
  return {{cx ? a : 0.0, cy ? b : 0.0}, {cx ? 1.0 : a, cy ? 1.0 : b}};
}

double uniformCornerMeasure(int cx, int cy, double a, double b) {
  return (cx ? 1 - a : a) * (cy ? 1 - b : b);
}

namespace {

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

}  // namespace

double exactL2Star(std::span<const Point2> p, const CornerMeasure &mu,
                   const std::vector<double> &xBreaks, const std::vector<double> &yBreaks) {
  return std::sqrt(exactCornerIntegral(p, 0, 0, mu, xBreaks, yBreaks));
}

double exactL2asd(std::span<const Point2> p, const CornerMeasure &mu,
                  const std::vector<double> &xBreaks, const std::vector<double> &yBreaks) {
  double s = 0;
  for (int cx = 0; cx < 2; ++cx)
    for (int cy = 0; cy < 2; ++cy) s += exactCornerIntegral(p, cx, cy, mu, xBreaks, yBreaks);
  return std::sqrt(s / 4);
}

std::vector<Point2> mapped(std::span<const Point2> u, const Target &t) {
  std::vector<Point2> x;
  for (const Point2 &q : u) x.push_back(t.invert(q).x);
  return x;
}

}  // namespace nuld::test
