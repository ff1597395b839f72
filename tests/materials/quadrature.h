#pragma once
// Deterministic integration of (possibly very peaked) functions over the
// unit square, for the materials tests: the expected histogram counts of the
// chi-square tests and the normalization checks.
//
// A tensor mesh is laid over the square: the caller's bin edges plus lines
// graded geometrically toward a known peak (the mirror direction of a sharp
// lobe, or the pole), so that even a lobe 1e-4 rad wide is resolved. Each
// mesh cell is then integrated adaptively: a 4 x 4 Gauss-Legendre rule
// against the same rule on the four quadrants, split until they agree.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <vector>

#include "sampler/point.h"

namespace nuld::test {

using Integrand = std::function<double(Point2)>;

// Gauss-Legendre 4-point rule on [-1, 1].
inline constexpr std::array<double, 4> kGaussNodes = {-0.8611363115940526, -0.3399810435848563,
                                                      0.3399810435848563, 0.8611363115940526};
inline constexpr std::array<double, 4> kGaussWeights = {0.3478548451374538, 0.6521451548625461,
                                                        0.6521451548625461, 0.3478548451374538};

inline double gauss4x4(const Integrand &f, const Box2 &b) {
  const double hx = 0.5 * (b.hi.x - b.lo.x), hy = 0.5 * (b.hi.y - b.lo.y);
  const double cx = b.lo.x + hx, cy = b.lo.y + hy;
  double sum = 0;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      sum += kGaussWeights[i] * kGaussWeights[j] *
             f({cx + hx * kGaussNodes[i], cy + hy * kGaussNodes[j]});
  return sum * hx * hy;
}

// Adaptive refinement of one rectangle whose 4 x 4 estimate is `whole`:
// done when the quadrants agree to relTol, or to densityTol times the area
// (so that the total absolute error stays below densityTol).
inline double integrateAdaptive(const Integrand &f, const Box2 &b, double whole, double relTol,
                                double densityTol, int depth) {
  const Point2 mid{0.5 * (b.lo.x + b.hi.x), 0.5 * (b.lo.y + b.hi.y)};
  const std::array<Box2, 4> quads = {Box2{b.lo, mid}, Box2{{mid.x, b.lo.y}, {b.hi.x, mid.y}},
                                     Box2{{b.lo.x, mid.y}, {mid.x, b.hi.y}}, Box2{mid, b.hi}};
  std::array<double, 4> parts{};
  double sum = 0;
  for (int k = 0; k < 4; ++k) sum += parts[k] = gauss4x4(f, quads[k]);
  const double tol = std::max(relTol * std::abs(sum), densityTol * b.area());
  if (depth <= 0 || std::abs(sum - whole) <= tol) return sum;
  double refined = 0;
  for (int k = 0; k < 4; ++k)
    refined += integrateAdaptive(f, quads[k], parts[k], relTol, densityTol, depth - 1);
  return refined;
}

// Where sharp features sit: mesh lines are graded toward each x and y.
struct Peak {
  std::vector<double> x, y;
};

// Mesh lines: `edges` plus lines at c +- h for every centre c and h = h0,
// h0/2, ... down to hMin, clipped to [edges.front(), edges.back()].
inline std::vector<double> meshLines(const std::vector<double> &edges,
                                     const std::vector<double> &centres, double h0, double hMin) {
  std::vector<double> lines = edges;
  for (const double c : centres) {
    lines.push_back(c);
    for (double h = h0; h >= hMin; h *= 0.5) {
      lines.push_back(c - h);
      lines.push_back(c + h);
    }
  }
  const double lo = edges.front(), hi = edges.back();
  std::erase_if(lines, [&](double t) { return !(t >= lo && t <= hi); });
  std::sort(lines.begin(), lines.end());
  lines.erase(std::unique(lines.begin(), lines.end()), lines.end());
  return lines;
}

// The integral of f over each cell of the grid with the given edges
// (row-major, rows along y), resolving `peak` with graded mesh lines.
inline std::vector<double> integrateCells(const Integrand &f, const std::vector<double> &xEdges,
                                          const std::vector<double> &yEdges, const Peak &peak = {},
                                          double relTol = 1e-5, double densityTol = 1e-7) {
  const std::size_t cols = xEdges.size() - 1, rows = yEdges.size() - 1;
  constexpr double kHMin = 1e-10;
  const auto xs = meshLines(xEdges, peak.x, xEdges[1] - xEdges[0], kHMin);
  const auto ys = meshLines(yEdges, peak.y, yEdges[1] - yEdges[0], kHMin);
  std::vector<double> cells(cols * rows, 0.0);
  std::size_t row = 0;
  for (std::size_t b = 0; b + 1 < ys.size(); ++b) {
    while (row + 1 < rows && ys[b] >= yEdges[row + 1]) ++row;
    std::size_t col = 0;
    for (std::size_t a = 0; a + 1 < xs.size(); ++a) {
      while (col + 1 < cols && xs[a] >= xEdges[col + 1]) ++col;
      const Box2 box{{xs[a], ys[b]}, {xs[a + 1], ys[b + 1]}};
      cells[row * cols + col] += integrateAdaptive(f, box, gauss4x4(f, box), relTol, densityTol, 6);
    }
  }
  return cells;
}

inline std::vector<double> uniformEdges(double lo, double hi, int cells) {
  std::vector<double> e(cells + 1);
  for (int i = 0; i <= cells; ++i) e[i] = lo + (hi - lo) * i / cells;
  e[cells] = hi;
  return e;
}

}  // namespace nuld::test
