// Non-uniform L2 discrepancies, integrated exactly against the bilinear
// interpolant F~ of the target's CDF (see CdfField). Expanding the square,
//   D^2 = int mu_c^2 - (2/N) sum_i int_{R_c(x_i)} mu_c + (1/N^2) sum_ij P_c(x_i, x_j),
// where R_c(x) is the set of box corners whose box contains x and P_c the
// area of the boxes containing both points: the same pair term as Warnock's
// formula. For uniform and piecewise-constant targets this is exact.
#include "sampler/metrics/nonuniform_l2.h"

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

// Gradient of the sum over the 4 corners of crossTerm with respect to p.
Point2 crossGradient(const CdfField &F, Point2 p) {
  const double x = std::clamp(p.x, 0.0, 1.0), y = std::clamp(p.y, 0.0, 1.0);
  const double colBelow = F.columnIntegral(x, y), colAll = F.columnIntegral(x, 1);
  const double rowLeft = F.rowIntegral(y, x), rowAll = F.rowIntegral(y, 1);
  const double R1 = F.rightIntegral(1), Ry = F.rightIntegral(y);
  const double T1 = F.topIntegral(1), Tx = F.topIntegral(x);
  const double Fx1 = F.value(x, 1), F1y = F.value(1, y);
  // Corners 0..3 as in crossTerm, differentiated term by term.
  const double gx = -(colAll - colBelow) + (R1 - Ry) - (colAll - colBelow) + (-y * Fx1 + colBelow) +
                    (y - y * Fx1 - Ry + colBelow);
  const double gy = -(rowAll - rowLeft) + (-x * F1y + rowLeft) + (T1 - Tx) - (rowAll - rowLeft) +
                    (x - Tx - x * F1y + rowLeft);
  return {gx, gy};
}

// Sum over i, j of the anchored-box areas containing both points (Warnock's pair term).
double starPairTerm(std::span<const Point2> p) {
  std::vector<double> rows(p.size());
  tbb::parallel_for(std::size_t(0), p.size(), [&](std::size_t i) {
    const double xi = std::clamp(p[i].x, 0.0, 1.0), yi = std::clamp(p[i].y, 0.0, 1.0);
    double s = 0;
    for (std::size_t j = 0; j < p.size(); ++j)
      s += (1 - std::max(xi, std::clamp(p[j].x, 0.0, 1.0))) *
           (1 - std::max(yi, std::clamp(p[j].y, 0.0, 1.0)));
    rows[i] = s;
  });
  return std::accumulate(rows.begin(), rows.end(), 0.0);
}

}  // namespace

NonuniformL2asd::NonuniformL2asd(const Target &target, int res)
    : field_(fieldFor(target, res)), massSquared_(squaredMassTerm(field_, {0, 1, 2, 3})) {}

double NonuniformL2asd::squared(std::span<const Point2> p, std::span<Point2> grad) const {
  if (p.empty()) throw std::invalid_argument("l2asd objective: empty point set");
  if (!grad.empty() && grad.size() != p.size())
    throw std::invalid_argument("l2asd objective: gradient size differs from the point count");
  const std::size_t n = p.size();
  const double N = double(n);
  std::vector<double> rowTerm(n);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
    double cross = 0;
    for (int c = 0; c < 4; ++c) cross += crossTerm(field_, c, p[i]);
    const double xi = std::clamp(p[i].x, 0.0, 1.0), yi = std::clamp(p[i].y, 0.0, 1.0);
    double pair = 0, gx = 0, gy = 0;
    for (std::size_t j = 0; j < n; ++j) {
      const double dx = xi - std::clamp(p[j].x, 0.0, 1.0), dy = yi - std::clamp(p[j].y, 0.0, 1.0);
      const double hx = 1 - std::abs(dx), hy = 1 - std::abs(dy);
      pair += hx * hy;
      gx -= (dx > 0 ? 1.0 : dx < 0 ? -1.0 : 0.0) * hy;
      gy -= (dy > 0 ? 1.0 : dy < 0 ? -1.0 : 0.0) * hx;
    }
    rowTerm[i] = -2 * cross / N + pair / (N * N);
    if (!grad.empty()) {
      const Point2 gc = crossGradient(field_, p[i]);
      // Symmetric pair terms count twice; the 1/4 averages the corners.
      grad[i] = {0.25 * (-2 * gc.x / N + 2 * gx / (N * N)),
                 0.25 * (-2 * gc.y / N + 2 * gy / (N * N))};
    }
  });
  return 0.25 * (massSquared_ + std::accumulate(rowTerm.begin(), rowTerm.end(), 0.0));
}

namespace {

double nonuniformL2StarSquared(std::span<const Point2> p, const Target &target, int res) {
  if (p.empty()) throw std::invalid_argument("l2: empty point set");
  const CdfField F = fieldFor(target, res);
  const double N = double(p.size());
  double cross = 0;
  for (const Point2 &q : p) cross += crossTerm(F, 0, q);
  return squaredMassTerm(F, {0}) - 2 * cross / N + starPairTerm(p) / (N * N);
}

}  // namespace

double nonuniformL2Star(std::span<const Point2> p, const Target &target, int res) {
  return std::sqrt(std::max(0.0, nonuniformL2StarSquared(p, target, res)));
}

double nonuniformL2asd(std::span<const Point2> p, const Target &target, int res) {
  return std::sqrt(std::max(0.0, NonuniformL2asd(target, res).squared(p)));
}

}  // namespace nuld
