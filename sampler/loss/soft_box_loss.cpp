#include "sampler/loss/soft_box_loss.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "sampler/loss/fast_exp.h"
#include "sampler/loss/point_grid.h"

namespace nuld {
namespace {

void validate(std::span<const Point2> points, std::span<const Box2> boxes,
              std::span<const double> masses) {
  if (masses.size() != boxes.size())
    throw std::invalid_argument("softBoxLoss: " + std::to_string(boxes.size()) + " boxes but " +
                                std::to_string(masses.size()) + " masses");
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!isFinite(points[i]))
      throw std::invalid_argument("softBoxLoss: point " + std::to_string(i) + " is not finite");
  for (std::size_t m = 0; m < masses.size(); ++m)
    if (!std::isfinite(masses[m]))
      throw std::invalid_argument("softBoxLoss: mass of box " + std::to_string(m) +
                                  " is not finite");
}

// A run of one storage order that a box scanned, and where its signed slopes
// start in the box's slope buffer.
struct ScannedRun {
  bool columnOrder;
  std::uint32_t begin, end, offset;
};

// Number of partial sums: a function of the problem size only, never of the
// thread count, so that results are bit-identical on any machine.
std::size_t chunkCount(std::size_t n, std::size_t m) {
  const std::size_t byBoxes = std::max<std::size_t>(1, m / 128);
  const std::size_t byMemory =
      std::max<std::size_t>(1, (std::size_t(1) << 22) / std::max<std::size_t>(n, 1));
  return std::min({byBoxes, byMemory, std::size_t(64)});
}

// One box's soft count over the points in its band, the cells its outer box
// touches less the whole cells deep inside it: each scanned point adds
// sigma(alpha d) for its signed distance d to the nearest side. With a
// gradient it also keeps each scanned point's dsigma/dx (sigma'(alpha d) on
// the nearest side's axis, signed by that side, zero outside the band) and
// the runs they came from, for addGradient. A box scans each point at most
// once, so N slopes suffice.
class BandScan {
 public:
  BandScan(const PointGrid &grid, double alpha, double cutoff, bool wantGrad)
      : grid_(grid),
        alpha_(alpha),
        cutoff_(cutoff),
        wantGrad_(wantGrad),
        slopes_(wantGrad ? grid.xs().size() : 0) {}

  // The soft count of box A, whose outer box touches `touch` and whose inner
  // box covers the whole cells `in`.
  double box(const Box2 &A, const PointGrid::CellRange &touch, const PointGrid::CellRange &in) {
    double soft = 0;
    used_ = 0;
    runs_.clear();
    if (touch.empty()) return soft;
    const auto rows = [&](int row0, int row1) {
      for (int row = row0; row <= row1; ++row)
        scan(A, false, grid_.cellBegin(touch.cx0, row), grid_.rowEnd(touch.cx1, row), soft);
    };
    if (in.empty()) {
      rows(touch.cy0, touch.cy1);
      return soft;
    }
    // Rows above and below the interior: whole rows of the touched range.
    rows(touch.cy0, in.cy0 - 1);
    rows(in.cy1 + 1, touch.cy1);
    // Columns left and right of the interior, over the interior's rows: one
    // contiguous run each in the column-major order.
    for (int col = touch.cx0; col < in.cx0; ++col)
      scan(A, true, grid_.columnBegin(col, in.cy0), grid_.columnEnd(col, in.cy1), soft);
    for (int col = in.cx1 + 1; col <= touch.cx1; ++col)
      scan(A, true, grid_.columnBegin(col, in.cy0), grid_.columnEnd(col, in.cy1), soft);
    return soft;
  }

  // Adds coef times the last box's slopes to the gradients kept in the grid's
  // row-major (gRow) and column-major (gCol) orders.
  void addGradient(double coef, Point2 *gRow, Point2 *gCol) const {
    for (const ScannedRun &run : runs_) {
      double *g = reinterpret_cast<double *>((run.columnOrder ? gCol : gRow) + run.begin);
      const double *sl = reinterpret_cast<const double *>(slopes_.data() + run.offset);
      const std::size_t len = 2 * std::size_t(run.end - run.begin);
      for (std::size_t k = 0; k < len; ++k) g[k] += coef * sl[k];
    }
  }

 private:
  // Evaluates the contiguous run [begin, end) of one storage order in
  // branch-free, vectorizable blocks, adding to `soft`.
  void scan(const Box2 &A, bool columnOrder, std::uint32_t begin, std::uint32_t end, double &soft) {
    if (begin >= end) return;
    const double alpha = alpha_, cutoff = cutoff_;
    const double *sx = columnOrder ? grid_.columnXs().data() : grid_.xs().data();
    const double *sy = columnOrder ? grid_.columnYs().data() : grid_.ys().data();
    Point2 *slope = wantGrad_ ? slopes_.data() + used_ : nullptr;
    if (wantGrad_) {
      if (end - begin > slopes_.size() - used_)
        throw std::logic_error("softBoxLoss: a box scanned a point twice");
      runs_.push_back({columnOrder, begin, end, used_});
      used_ += end - begin;
    }
    constexpr std::uint32_t kBlock = 64;
    alignas(64) double value[kBlock], slopeX[kBlock], slopeY[kBlock];
    for (std::uint32_t k0 = begin; k0 < end; k0 += kBlock) {
      const int n = int(std::min(kBlock, end - k0));
      const double *bx = sx + k0, *by = sy + k0;
      for (int j = 0; j < n; ++j) {
        const double toLoX = bx[j] - A.lo.x, toHiX = A.hi.x - bx[j];
        const double toLoY = by[j] - A.lo.y, toHiY = A.hi.y - by[j];
        const double dX = std::min(toLoX, toHiX), dY = std::min(toLoY, toHiY);
        const double at = alpha * std::min(dX, dY);
        const double a = std::min(std::abs(at), cutoff);
        const double e = fastExpNonPositive(-a);
        const double inv = 1 / (1 + e);
        const bool band = std::abs(at) <= cutoff;
        value[j] = at > cutoff ? 1.0 : band ? (at >= 0 ? inv : e * inv) : 0.0;
        // The nearest side, ties to the first of lo x, hi x, lo y, hi y.
        const double ds = band ? e * inv * inv : 0.0;
        const bool onX = dX <= dY;
        slopeX[j] = onX ? (toLoX <= toHiX ? ds : -ds) : 0.0;
        slopeY[j] = onX ? 0.0 : (toLoY <= toHiY ? ds : -ds);
      }
      if (wantGrad_) {
        Point2 *sl = slope + (k0 - begin);
        for (int j = 0; j < n; ++j) sl[j] = {slopeX[j], slopeY[j]};
      }
      double partial[4] = {0, 0, 0, 0};
      for (int j = 0; j < n; ++j) partial[j & 3] += value[j];
      soft += (partial[0] + partial[1]) + (partial[2] + partial[3]);
    }
  }

  const PointGrid &grid_;
  const double alpha_, cutoff_;
  const bool wantGrad_;
  std::vector<Point2> slopes_;
  std::vector<ScannedRun> runs_;
  std::uint32_t used_ = 0;
};

// Sums the chunks' gradients in a fixed order per storage slot, then maps
// both storage orders back to the caller's indices.
void gatherGradient(const PointGrid &grid, std::span<const Point2> chunkGrad, std::size_t chunks,
                    std::span<Point2> grad) {
  const std::size_t N = grad.size();
  std::vector<Point2> total(2 * N);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, 2 * N, 1024), [&](const auto &r) {
    for (std::size_t k = r.begin(); k < r.end(); ++k) {
      Point2 sum{};
      for (std::size_t c = 0; c < chunks; ++c) sum = sum + chunkGrad[2 * c * N + k];
      total[k] = sum;
    }
  });
  const std::uint32_t *ri = grid.originalIndex().data(), *ci = grid.columnIndex().data();
  for (std::size_t k = 0; k < N; ++k) grad[ri[k]] = total[k];
  for (std::size_t k = 0; k < N; ++k) grad[ci[k]] = grad[ci[k]] + total[N + k];
}

}  // namespace

double softBoxLoss(std::span<const Point2> points, std::span<const Box2> boxes,
                   std::span<const double> masses, const SoftBoxLossOptions &options,
                   std::span<Point2> grad) {
  validate(points, boxes, masses);
  if (!(options.alpha > 0) || !std::isfinite(options.alpha))
    throw std::invalid_argument("softBoxLoss: alpha must be finite and > 0");
  const bool wantGrad = !grad.empty();
  if (wantGrad && grad.size() != points.size())
    throw std::invalid_argument("softBoxLoss: gradient size differs from the point count");
  const std::size_t N = points.size(), M = boxes.size();
  if (wantGrad) std::fill(grad.begin(), grad.end(), Point2{});
  if (M == 0) return 0;
  if (N == 0) {
    double loss = 0;
    for (double mu : masses) loss += mu * mu;
    return loss / double(M);
  }

  const PointGrid grid(points, {}, 0, /*columnOrder=*/true);
  const double alpha = options.alpha, cutoff = options.cutoff;
  const double delta = cutoff / alpha;  // half-width of the band around each side
  const double invN = 1.0 / double(N);
  const double gradScale = 2.0 * alpha / (double(M) * double(N));

  // Gradients accumulate per chunk in the grid's two storage orders, so that
  // a box adds its slopes to contiguous runs (vectorized) rather than
  // scattering them by original index; they are mapped back once at the end.
  const std::size_t chunks = chunkCount(N, M);
  std::vector<double> chunkLoss(chunks, 0.0);
  std::vector<Point2> chunkGrad(wantGrad ? 2 * chunks * N : 0);

  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    const std::size_t m0 = M * c / chunks, m1 = M * (c + 1) / chunks;
    Point2 *gRow = wantGrad ? &chunkGrad[2 * c * N] : nullptr;
    Point2 *gCol = wantGrad ? gRow + N : nullptr;
    BandScan scan(grid, alpha, cutoff, wantGrad);
    double lossSum = 0;
    for (std::size_t m = m0; m < m1; ++m) {
      const Box2 &A = boxes[m];
      const Box2 inner{{A.lo.x + delta, A.lo.y + delta}, {A.hi.x - delta, A.hi.y - delta}};
      const Box2 outer{{A.lo.x - delta, A.lo.y - delta}, {A.hi.x + delta, A.hi.y + delta}};
      const PointGrid::CellRange in = grid.cellsInside(inner);
      const double count = grid.cellSum(in);  // whole cells deep inside: sigma = 1
      const double soft = scan.box(A, grid.cellsTouching(outer), in);
      const double r = (count + soft) * invN - masses[m];
      lossSum += r * r;
      if (wantGrad && r != 0) scan.addGradient(gradScale * r, gRow, gCol);
    }
    chunkLoss[c] = lossSum;
  });
  if (wantGrad) gatherGradient(grid, chunkGrad, chunks, grad);
  double loss = 0;
  for (double l : chunkLoss) loss += l;
  return loss / double(M);
}

double hardBoxLoss(std::span<const Point2> points, std::span<const Box2> boxes,
                   std::span<const double> masses) {
  validate(points, boxes, masses);
  if (boxes.empty()) return 0;
  double loss = 0;
  for (std::size_t m = 0; m < boxes.size(); ++m) {
    std::size_t inside = 0;
    for (const Point2 &p : points) inside += boxes[m].contains(p);
    const double r = (points.empty() ? 0.0 : double(inside) / double(points.size())) - masses[m];
    loss += r * r;
  }
  return loss / double(boxes.size());
}

}  // namespace nuld
