#include "sampler/metrics/discrepancy.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace nuld {
namespace {

// Deterministic parallel sum of f(i) over [0, n): fixed blocks summed in order.
template <typename F>
double orderedSum(std::size_t n, F f) {
  constexpr std::size_t kBlock = 64;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<double> partial(blocks, 0.0);
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
    double s = 0;
    for (std::size_t i = b * kBlock, e = std::min(n, (b + 1) * kBlock); i < e; ++i) s += f(i);
    partial[b] = s;
  });
  return std::accumulate(partial.begin(), partial.end(), 0.0);
}

void requireNonEmpty(std::span<const Point2> points, const char *what) {
  if (points.empty()) throw std::invalid_argument(std::string(what) + ": empty point set");
}

}  // namespace

double l2StarDiscrepancy(std::span<const Point2> p) {
  requireNonEmpty(p, "l2star");
  const double N = double(p.size());
  const double single = orderedSum(
      p.size(), [&](std::size_t i) { return (1 - p[i].x * p[i].x) * (1 - p[i].y * p[i].y); });
  const double pairs = orderedSum(p.size(), [&](std::size_t i) {
    double s = 0;
    for (std::size_t j = 0; j < p.size(); ++j)
      s += (1 - std::max(p[i].x, p[j].x)) * (1 - std::max(p[i].y, p[j].y));
    return s;
  });
  const double t2 = 1.0 / 9.0 - single / (2 * N) + pairs / (N * N);
  return std::sqrt(std::max(0.0, t2));
}

double l2asd(std::span<const Point2> p) {
  requireNonEmpty(p, "l2asd");
  const double N = double(p.size());
  const double single = orderedSum(p.size(), [&](std::size_t i) {
    return (1 + 2 * p[i].x - 2 * p[i].x * p[i].x) * (1 + 2 * p[i].y - 2 * p[i].y * p[i].y) / 16;
  });
  const double pairs = orderedSum(p.size(), [&](std::size_t i) {
    double s = 0;
    for (std::size_t j = 0; j < p.size(); ++j)
      s += (1 - std::abs(p[i].x - p[j].x)) * (1 - std::abs(p[i].y - p[j].y));
    return s;
  });
  const double d2 = 1.0 / 9.0 - 2 * single / N + pairs / (4 * N * N);
  return std::sqrt(std::max(0.0, d2));
}

double periodicL2Squared(std::span<const Point2> p, std::span<Point2> grad) {
  requireNonEmpty(p, "l2per");
  if (!grad.empty() && grad.size() != p.size())
    throw std::invalid_argument("l2per: gradient size does not match the points");
  const std::size_t n = p.size();
  const double N = double(n);
  // The kernel of one coordinate: the probability that a random toroidal
  // interval holds two points d apart (along the interval's direction).
  auto kernel = [](double d) { return 0.5 - d * (1 - d); };
  const double pairs = orderedSum(n, [&](std::size_t i) {
    double s = 0;
    Point2 g{};
    for (std::size_t j = 0; j < n; ++j) {
      const double dx = wrapUnit(p[i].x - p[j].x), dy = wrapUnit(p[i].y - p[j].y);
      const double kx = kernel(dx), ky = kernel(dy);
      s += kx * ky;
      if (j == i) continue;  // the diagonal term is a constant
      // d(kernel(frac(xi - xj)))/dxi = 2 d - 1; the pair (j, i) has
      // d' = 1 - d and the same derivative, hence the factor 2 below.
      g.x += (2 * dx - 1) * ky;
      g.y += (2 * dy - 1) * kx;
    }
    if (!grad.empty()) grad[i] = (2 / (N * N)) * g;
    return s;
  });
  return pairs / (N * N) - 1.0 / 9.0;
}

double periodicL2(std::span<const Point2> p) {
  return std::sqrt(std::max(0.0, periodicL2Squared(p)));
}

double starDiscrepancy(std::span<const Point2> p, const Target *target) {
  requireNonEmpty(p, "dstar");
  const std::size_t n = p.size();
  const double N = double(n);
  auto mu = [&](double a, double b) {
    return target ? target->mass({{0, 0}, {a, b}})
                  : std::clamp(a, 0.0, 1.0) * std::clamp(b, 0.0, 1.0);
  };
  // Points in increasing y; the critical a values are every x and 1.
  std::vector<Point2> byY(p.begin(), p.end());
  std::sort(byY.begin(), byY.end(), [](Point2 a, Point2 b) { return a.y < b.y; });
  std::vector<double> as;
  as.reserve(n + 1);
  for (const Point2 &q : p) as.push_back(std::clamp(q.x, 0.0, 1.0));
  as.push_back(1.0);
  std::sort(as.begin(), as.end());
  as.erase(std::unique(as.begin(), as.end()), as.end());

  std::vector<double> best(as.size(), 0.0);
  tbb::parallel_for(std::size_t(0), as.size(), [&](std::size_t ia) {
    const double a = as[ia];
    std::size_t open = 0, closed = 0;  // counts with x < a (resp. <= a) and y below b
    double d = 0;
    for (std::size_t k = 0; k < n;) {
      const double b = std::clamp(byY[k].y, 0.0, 1.0);
      const double m = mu(a, b);
      d = std::max(d, m - open / N);  // box [0,a) x [0,b): open counts so far
      std::size_t k2 = k;
      for (; k2 < n && byY[k2].y == byY[k].y; ++k2) {
        open += byY[k2].x < a;
        closed += byY[k2].x <= a;
      }
      d = std::max(d, closed / N - m);  // box [0,a] x [0,b]
      k = k2;
    }
    d = std::max(d, mu(a, 1.0) - open / N);
    best[ia] = d;
  });
  return *std::max_element(best.begin(), best.end());
}

double discrepancyByName(const std::string &metric, std::span<const Point2> points,
                         const Target &target, int res) {
  const bool uniform = target.isUniform();
  if (metric == "l2star")
    return uniform ? l2StarDiscrepancy(points) : nonuniformL2Star(points, target, res);
  if (metric == "l2asd") return uniform ? l2asd(points) : nonuniformL2asd(points, target, res);
  if (metric == "dstar") return starDiscrepancy(points, uniform ? nullptr : &target);
  if (metric == "l2") return nonuniformL2asd(points, target, res);
  if (metric == "l2per") {
    if (!uniform)
      throw std::invalid_argument("l2per measures uniform sets on the torus; the target is '" +
                                  target.spec() + "'");
    return periodicL2(points);
  }
  throw std::invalid_argument("unknown metric '" + metric +
                              "' (expected l2star, l2asd, dstar, l2 or l2per)");
}

}  // namespace nuld
