// Non-uniform L2 discrepancies, integrated exactly against the bilinear
// interpolant F~ of the target's CDF (see CdfField). Expanding the square,
//   D^2 = int mu_c^2 - (2/N) sum_i int_{R_c(x_i)} mu_c + (1/N^2) sum_ij P_c(x_i, x_j),
// where R_c(x) is the set of box corners whose box contains x and P_c the
// area of the boxes containing both points: the same pair term as Warnock's
// formula. For uniform and piecewise-constant targets this is exact.
#include "sampler/metrics/nonuniform_l2.h"

#include <tbb/blocked_range.h>
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
    return CdfField(grid->xEdges(), grid->yEdges(), grid->nodeCdf());  // exact
  if (res < 1) throw std::invalid_argument("l2: grid resolution must be >= 1");
  std::vector<double> nodes(res + 1);
  for (int i = 0; i <= res; ++i) nodes[i] = double(i) / res;
  return CdfField(target, nodes, nodes);
}

// Integral over a cell of area `area` of the square of the bilinear function
// with corner values v00, v10, v01, v11 (first index along x): the tensor
// product of the 1D mass matrix {{1/3, 1/6}, {1/6, 1/3}}, written out.
inline double cellSquareIntegral(double v00, double v10, double v01, double v11, double area) {
  return area * ((v00 * v00 + v10 * v10 + v01 * v01 + v11 * v11 + v00 * v10 + v01 * v11 +
                  v00 * v01 + v10 * v11) /
                     9 +
                 (v00 * v11 + v10 * v01) / 18);
}

// Sum over corner boxes c in `corners` (bit 0: x side, bit 1: y side; 0 means
// the box starts at 0) of the integral of mu_c^2. The box masses at a node
// (a, b) follow from F(a, b), F(a, 1) and F(1, b): [0,a] x [0,b] is F,
// [a,1] x [0,b] is F(1, b) - F, [0,a] x [b,1] is F(a, 1) - F and [a,1] x
// [b,1] is 1 - F(a, 1) - F(1, b) + F. Every bank optimized for a map pays
// this once, over all of its cells.
double squaredMassTerm(const CdfField &F, const std::vector<int> &corners) {
  const int C = F.cols(), R = F.rows();
  bool use[4] = {false, false, false, false};
  for (int c : corners) use[c] = true;
  std::vector<double> rowSums(R, 0.0);
  tbb::parallel_for(0, R, [&](int j) {
    const double dy = F.yNode(j + 1) - F.yNode(j);
    const double r0 = F.node(C, j), r1 = F.node(C, j + 1);  // F(1, b) on the cell's two rows
    double s = 0;
    for (int i = 0; i < C; ++i) {
      const double area = (F.xNode(i + 1) - F.xNode(i)) * dy;
      const double t0 = F.node(i, R), t1 = F.node(i + 1, R);  // F(a, 1) on its two columns
      const double f00 = F.node(i, j), f10 = F.node(i + 1, j), f01 = F.node(i, j + 1),
                   f11 = F.node(i + 1, j + 1);
      if (use[0]) s += cellSquareIntegral(f00, f10, f01, f11, area);
      if (use[1]) s += cellSquareIntegral(r0 - f00, r0 - f10, r1 - f01, r1 - f11, area);
      if (use[2]) s += cellSquareIntegral(t0 - f00, t1 - f10, t0 - f01, t1 - f11, area);
      if (use[3])
        s += cellSquareIntegral(1 - t0 - r0 + f00, 1 - t1 - r0 + f10, 1 - t0 - r1 + f01,
                                1 - t1 - r1 + f11, area);
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
  const auto rowLoss = [&](std::size_t i) {
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
  };
  // Rows in chunks of about 16K pair terms: a bank's small sets (N = 16 or
  // 64, already optimized in parallel by instance) would otherwise spend
  // more on scheduling a task per row than on the row. The sum's order is
  // the rows' either way.
  const std::size_t grain = std::max<std::size_t>(1, (std::size_t(1) << 14) / n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const auto &rows) {
    for (std::size_t i = rows.begin(); i != rows.end(); ++i) rowLoss(i);
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
