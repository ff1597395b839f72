// Non-uniform L2 discrepancies, integrated exactly against the bilinear
// interpolant F~ of the target's CDF (see CdfField). Expanding the square,
//   D^2 = int mu_c^2 - (2/N) sum_i int_{R_c(x_i)} mu_c + (1/N^2) sum_ij P_c(x_i, x_j),
// where R_c(x) is the set of box corners whose box contains x and P_c the
// area of the boxes containing both points: the same pair term as Warnock's
// formula. For uniform and piecewise-constant targets this is exact.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "sampler/metrics/cdf_field.h"
#include "sampler/metrics/discrepancy.h"
#include "sampler/targets/grid_target.h"

namespace nuld {
namespace {

CdfField fieldFor(const Target &target, int res) {
  if (const auto *grid = dynamic_cast<const GridTarget *>(&target))
    return CdfField(target, grid->xEdges(), grid->yEdges());  // exact
  if (res < 1) throw std::invalid_argument("l2: grid resolution must be >= 1");
  std::vector<double> nodes(res + 1);
  for (int i = 0; i <= res; ++i) nodes[i] = double(i) / res;
  return CdfField(target, nodes, nodes);
}

// Integral over one cell of the square of the bilinear function with corner
// values v[k][l] (k along x): the tensor product of the 1D mass matrix.
double cellSquareIntegral(const double v[2][2], double area) {
  constexpr double m[2][2] = {{1.0 / 3, 1.0 / 6}, {1.0 / 6, 1.0 / 3}};
  double s = 0;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c)
        for (int d = 0; d < 2; ++d) s += v[a][b] * v[c][d] * m[a][c] * m[b][d];
  return s * area;
}

// Sum over corner boxes c in `corners` (bit 0: x side, bit 1: y side; 0 means
// the box starts at 0) of the integral of mu_c^2.
double squaredMassTerm(const CdfField &F, const std::vector<int> &corners) {
  const int C = F.cols(), R = F.rows();
  std::vector<double> rowSums(R, 0.0);
  tbb::parallel_for(0, R, [&](int j) {
    double s = 0;
    for (int i = 0; i < C; ++i) {
      const double area = (F.xNode(i + 1) - F.xNode(i)) * (F.yNode(j + 1) - F.yNode(j));
      for (int c : corners) {
        double v[2][2];
        for (int k = 0; k < 2; ++k)
          for (int l = 0; l < 2; ++l) {
            const double f = F.node(i + k, j + l), ft = F.node(i + k, R), fr = F.node(C, j + l);
            switch (c) {
              case 0: v[k][l] = f; break;                 // [0,a] x [0,b]
              case 1: v[k][l] = fr - f; break;            // [a,1] x [0,b]
              case 2: v[k][l] = ft - f; break;            // [0,a] x [b,1]
              default: v[k][l] = 1 - ft - fr + f; break;  // [a,1] x [b,1]
            }
          }
        s += cellSquareIntegral(v, area);
      }
    }
    rowSums[j] = s;
  });
  return std::accumulate(rowSums.begin(), rowSums.end(), 0.0);
}

// Integral of mu_c over the box corners (a, b) whose box contains p.
double crossTerm(const CdfField &F, int c, Point2 p) {
  const double x = std::clamp(p.x, 0.0, 1.0), y = std::clamp(p.y, 0.0, 1.0);
  switch (c) {
    case 0: return F.rectIntegral(x, 1, y, 1);
    case 1: return x * (F.rightIntegral(1) - F.rightIntegral(y)) - F.rectIntegral(0, x, y, 1);
    case 2: return y * (F.topIntegral(1) - F.topIntegral(x)) - F.rectIntegral(x, 1, 0, y);
    default:
      return x * y - y * F.topIntegral(x) - x * F.rightIntegral(y) + F.rectIntegral(0, x, 0, y);
  }
}

// Sum over i, j of the corner-box areas containing both points.
double pairTerm(std::span<const Point2> p, bool allCorners) {
  std::vector<double> rows(p.size());
  tbb::parallel_for(std::size_t(0), p.size(), [&](std::size_t i) {
    const double xi = std::clamp(p[i].x, 0.0, 1.0), yi = std::clamp(p[i].y, 0.0, 1.0);
    double s = 0;
    for (std::size_t j = 0; j < p.size(); ++j) {
      const double xj = std::clamp(p[j].x, 0.0, 1.0), yj = std::clamp(p[j].y, 0.0, 1.0);
      s += allCorners ? (1 - std::abs(xi - xj)) * (1 - std::abs(yi - yj))
                      : (1 - std::max(xi, xj)) * (1 - std::max(yi, yj));
    }
    rows[i] = s;
  });
  return std::accumulate(rows.begin(), rows.end(), 0.0);
}

double nonuniformL2(std::span<const Point2> p, const Target &target, int res, bool allCorners) {
  if (p.empty()) throw std::invalid_argument("l2: empty point set");
  const CdfField F = fieldFor(target, res);
  const std::vector<int> corners = allCorners ? std::vector<int>{0, 1, 2, 3} : std::vector<int>{0};
  const double N = double(p.size());
  double cross = 0;
  for (const Point2 &q : p)
    for (int c : corners) cross += crossTerm(F, c, q);
  const double d2 = squaredMassTerm(F, corners) - 2 * cross / N + pairTerm(p, allCorners) / (N * N);
  return std::sqrt(std::max(0.0, d2 / double(corners.size())));
}

}  // namespace

double nonuniformL2Star(std::span<const Point2> p, const Target &target, int res) {
  return nonuniformL2(p, target, res, false);
}

double nonuniformL2asd(std::span<const Point2> p, const Target &target, int res) {
  return nonuniformL2(p, target, res, true);
}

}  // namespace nuld
