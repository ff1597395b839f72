#include "sampler/loss/soft_box_loss.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "sampler/loss/lanes.h"
#include "sampler/loss/point_grid.h"
#include "sampler/loss/soft_box_kernels.h"

namespace nuld {
namespace {

using soft_box::DirectKernel;
using soft_box::Exponentials;
using soft_box::FactoredKernel;
using soft_box::factorsRepresentable;
using soft_box::PairLanes;
using soft_box::PointColumns;

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
// start in the box's slope buffers.
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
  return std::min({byBoxes, byMemory, std::size_t(16)});
}

// Gradients of one chunk of boxes, one array per coordinate, each holding
// the grid's row order and then its column order (2 N slots).
struct ChunkGradient {
  double *x, *y;
};

// One box's soft count over the points in its band, the cells its outer box
// touches less the whole cells deep inside it: each scanned point adds
// sigma(alpha d) for its signed distance d to the nearest side. With a
// gradient it also keeps each scanned point's dsigma/dx (sigma'(alpha d) on
// the nearest side's axis, signed by that side, zero outside the band) for
// addGradient. A box scans each point at most once, so N slopes (and a
// vector's worth of slack) suffice.
//
// Two ways to go through the scanned runs of points:
//  * FactoredKernel evaluates every scanned point where it lies and keeps
//    the slopes run by run: its wide bands leave few scanned points outside.
//  * DirectKernel first sorts the scanned points: those deep inside count 1,
//    those outside 0, and only the ones in the band are copied out and then
//    evaluated, a full vector at a time. With a narrow band most scanned
//    points (whole cells) lie outside it, and the exp and division are most
//    of a pair's cost.
template <class Kernel>
class BandScan {
 public:
  static_assert(PointGrid::kSlack >= lanes::kWidth, "vector loads run past a run's end");
  static constexpr bool kCompacts = std::is_same_v<Kernel, DirectKernel>;

  BandScan(const PointGrid &grid, const PointColumns &rowOrder, const PointColumns &columnOrder,
           double alpha, double cutoff, bool wantGrad)
      : grid_(grid),
        rowOrder_(rowOrder),
        columnOrder_(columnOrder),
        scale_(alpha, cutoff),
        wantGrad_(wantGrad),
        slopeX_(wantGrad ? grid.size() + lanes::kWidth : 0),
        slopeY_(slopeX_.size()) {
    runs_.reserve(64);
    if (kCompacts) {
      bandX_.assign(grid.size() + lanes::kWidth, 0.0);
      bandY_.assign(bandX_.size(), 0.0);
      bandSlot_.assign(bandX_.size(), 0.0);
    }
  }

  // The soft count of box A, whose outer box touches `touch` and whose inner
  // box covers the whole cells `in`.
  double box(const Box2 &A, const PointGrid::CellRange &touch, const PointGrid::CellRange &in) {
    lanes::Doubles soft{};
    used_ = 0;
    runs_.clear();
    if (touch.empty()) return 0;
    const Kernel kernel(A, scale_);
    // Whole rows of the touched range; rows spanning every column are one
    // contiguous run together.
    const bool fullWidth = touch.cx0 == 0 && touch.cx1 == grid_.resolution() - 1;
    const auto rows = [&](int row0, int row1) {
      if (row0 > row1) return;
      if (fullWidth) {
        scan(kernel, false, grid_.cellBegin(0, row0), grid_.rowEnd(touch.cx1, row1), soft);
        return;
      }
      for (int row = row0; row <= row1; ++row)
        scan(kernel, false, grid_.cellBegin(touch.cx0, row), grid_.rowEnd(touch.cx1, row), soft);
    };
    if (in.empty()) {
      rows(touch.cy0, touch.cy1);
    } else {
      // Rows above and below the interior: whole rows of the touched range.
      rows(touch.cy0, in.cy0 - 1);
      rows(in.cy1 + 1, touch.cy1);
      // Columns left and right of the interior, over the interior's rows:
      // one contiguous run each in the column-major order.
      for (int col = touch.cx0; col < in.cx0; ++col)
        scan(kernel, true, grid_.columnBegin(col, in.cy0), grid_.columnEnd(col, in.cy1), soft);
      for (int col = in.cx1 + 1; col <= touch.cx1; ++col)
        scan(kernel, true, grid_.columnBegin(col, in.cy0), grid_.columnEnd(col, in.cy1), soft);
    }
    if (kCompacts) evaluateBand(kernel, soft);
    return lanes::sum(soft);
  }

  // Adds coef times the last box's slopes to a chunk's gradients.
  void addGradient(double coef, const ChunkGradient &g) const {
    if (kCompacts) {
      for (std::uint32_t i = 0; i < used_; ++i) {
        const auto slot = std::size_t(bandSlot_[i]);
        g.x[slot] += coef * slopeX_[i];
        g.y[slot] += coef * slopeY_[i];
      }
      return;
    }
    for (const ScannedRun &run : runs_) {
      double *gx = g.x + run.begin + (run.columnOrder ? grid_.size() : 0);
      double *gy = g.y + run.begin + (run.columnOrder ? grid_.size() : 0);
      const double *sx = slopeX_.data() + run.offset, *sy = slopeY_.data() + run.offset;
      const std::uint32_t len = run.end - run.begin;
      for (std::uint32_t k = 0; k < len; ++k) gx[k] += coef * sx[k];
      for (std::uint32_t k = 0; k < len; ++k) gy[k] += coef * sy[k];
    }
  }

 private:
  // Goes through the contiguous run [begin, end) of one storage order a
  // vector of points at a time. The last vector reads into the slack and
  // masks the lanes past the run.
  [[gnu::always_inline]] void scan(const Kernel &kernel, bool columnOrder, std::uint32_t begin,
                                   std::uint32_t end, lanes::Doubles &soft) {
    if (begin >= end) return;
    const PointColumns &points = columnOrder ? columnOrder_ : rowOrder_;
    const std::uint32_t len = end - begin;
    if (len > grid_.size() - used_)
      throw std::logic_error("softBoxLoss: a box scanned a point twice");
    if constexpr (kCompacts) {
      // Slots in the chunk gradients: row order first, then column order.
      const double slot0 = double(begin + (columnOrder ? grid_.size() : 0));
      const lanes::Doubles iota = __builtin_convertvector(lanes::laneIndex(), lanes::Doubles);
      for (std::uint32_t k = 0; k < len; k += lanes::kWidth) {
        const auto c = kernel.classify(points, begin + k);
        const lanes::Mask valid = lanes::firstLanes(len - k);
        soft += (c.inside & valid) ? lanes::broadcast(1.0) : lanes::Doubles{};
        const lanes::Mask band = c.band & valid;
        lanes::compress(band, c.x, &bandX_[used_]);
        lanes::compress(band, c.y, &bandY_[used_]);
        used_ += std::uint32_t(
            lanes::compress(band, lanes::broadcast(slot0 + double(k)) + iota, &bandSlot_[used_]));
      }
    } else {
      double *outX = nullptr, *outY = nullptr;
      if (wantGrad_) {
        runs_.push_back({columnOrder, begin, end, used_});
        outX = slopeX_.data() + used_;
        outY = slopeY_.data() + used_;
      }
      used_ += len;
      std::uint32_t k = 0;
      // Two vectors per step: two independent chains through the division
      // keep the pipelines fuller.
      for (; k + 2 * lanes::kWidth <= len; k += 2 * lanes::kWidth) {
        const PairLanes p0 = kernel.evaluate(points, begin + k, wantGrad_);
        const PairLanes p1 = kernel.evaluate(points, begin + k + lanes::kWidth, wantGrad_);
        soft += p0.value + p1.value;
        if (!wantGrad_) continue;
        lanes::store(outX + k, p0.slopeX);
        lanes::store(outY + k, p0.slopeY);
        lanes::store(outX + k + lanes::kWidth, p1.slopeX);
        lanes::store(outY + k + lanes::kWidth, p1.slopeY);
      }
      for (; k < len; k += lanes::kWidth) {
        const PairLanes p = kernel.evaluate(points, begin + k, wantGrad_);
        soft += lanes::firstLanes(len - k) ? p.value : lanes::Doubles{};
        if (!wantGrad_) continue;
        // Lanes past the run land in the buffers' slack or under the next
        // run's slopes, and addGradient never reads them.
        lanes::store(outX + k, p.slopeX);
        lanes::store(outY + k, p.slopeY);
      }
    }
  }

  // sigma and the slopes of the points copied out of the band.
  void evaluateBand(const Kernel &kernel, lanes::Doubles &soft) {
    const PointColumns band{bandX_.data(), bandY_.data()};
    for (std::uint32_t k = 0; k < used_; k += lanes::kWidth) {
      const PairLanes p = kernel.evaluate(band, k, wantGrad_);
      soft += lanes::firstLanes(used_ - k) ? p.value : lanes::Doubles{};
      if (!wantGrad_) continue;
      lanes::store(&slopeX_[k], p.slopeX);
      lanes::store(&slopeY_[k], p.slopeY);
    }
  }

  const PointGrid &grid_;
  const PointColumns rowOrder_, columnOrder_;
  const typename Kernel::Scale scale_;
  const bool wantGrad_;
  std::vector<double> slopeX_, slopeY_;
  std::vector<ScannedRun> runs_;                  // FactoredKernel: the runs the slopes came from
  std::vector<double> bandX_, bandY_, bandSlot_;  // DirectKernel: the band's points, slots
  std::uint32_t used_ = 0;  // slopes kept (FactoredKernel) or points in the band (DirectKernel)
};

// Sums the chunks' gradients (4 N doubles each: row x, column x, row y,
// column y) in a fixed order per storage slot, then maps both storage orders
// back to the caller's indices.
void gatherGradient(const PointGrid &grid, std::span<const double> chunkGrad, std::size_t chunks,
                    std::span<Point2> grad) {
  const std::size_t N = grad.size();
  std::vector<double> total(4 * N);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, 4 * N, 2048), [&](const auto &r) {
    for (std::size_t k = r.begin(); k < r.end(); ++k) {
      double sum = 0;
      for (std::size_t c = 0; c < chunks; ++c) sum += chunkGrad[4 * c * N + k];
      total[k] = sum;
    }
  });
  const std::uint32_t *ri = grid.originalIndex().data(), *ci = grid.columnIndex().data();
  for (std::size_t k = 0; k < N; ++k) grad[ri[k]] = {total[k], total[2 * N + k]};
  for (std::size_t k = 0; k < N; ++k)
    grad[ci[k]] = grad[ci[k]] + Point2{total[N + k], total[3 * N + k]};
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

  const double alpha = options.alpha, cutoff = options.cutoff;
  const double delta = cutoff / alpha;  // half-width of the band around each side
  const PointGrid grid(points, {}, 0, /*columnOrder=*/true);
  const double invN = 1.0 / double(N);
  const double gradScale = 2.0 * alpha / (double(M) * double(N));

  // Gradients accumulate per chunk in the grid's two storage orders, so that
  // a box adds its slopes to contiguous runs (vectorized) rather than
  // scattering them by original index; they are mapped back once at the end.
  const std::size_t chunks = chunkCount(N, M);
  std::vector<double> chunkLoss(chunks, 0.0);
  std::vector<double> chunkGrad(wantGrad ? 4 * chunks * N : 0);

  const auto run = [&]<class Kernel>(const PointColumns &rowOrder,
                                     const PointColumns &columnOrder) {
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
      const std::size_t m0 = M * c / chunks, m1 = M * (c + 1) / chunks;
      ChunkGradient g{};
      if (wantGrad) {
        g.x = &chunkGrad[4 * c * N];
        g.y = g.x + 2 * N;
      }
      BandScan<Kernel> scan(grid, rowOrder, columnOrder, alpha, cutoff, wantGrad);
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
        if (wantGrad && r != 0) scan.addGradient(gradScale * r, g);
      }
      chunkLoss[c] = lossSum;
    });
  };
  // A band wider than a cell leaves few scanned points outside it: evaluate
  // them all with the cheaper FactoredKernel. A narrower one (late epochs)
  // is mostly whole cells outside it: DirectKernel sorts them out first.
  // The switch is where the two cost the same on a 2048-point set
  // (tools/experiments/optimizer_speed.md).
  const bool factored = [&] {
    switch (options.kernel) {
      case SoftBoxKernel::Direct: return false;
      case SoftBoxKernel::Factored:
        if (!factorsRepresentable(points, alpha, cutoff))
          throw std::invalid_argument(
              "softBoxLoss: the factored kernel needs points in the unit square and alpha / " +
              std::to_string(2 * FactoredKernel::kTiles) + " + cutoff <= 700");
        return true;
      case SoftBoxKernel::Automatic: break;
    }
    const bool wideBand = 2 * delta * grid.resolution() >= 1;
    return wideBand && factorsRepresentable(points, alpha, cutoff);
  }();
  if (factored) {
    const Exponentials rowOrder(grid.xs(), grid.ys(), N, alpha);
    const Exponentials columnOrder(grid.columnXs(), grid.columnYs(), N, alpha);
    run.template operator()<FactoredKernel>(rowOrder.columns(), columnOrder.columns());
  } else {
    run.template operator()<DirectKernel>({grid.xs(), grid.ys()},
                                          {grid.columnXs(), grid.columnYs()});
  }
  if (wantGrad) gatherGradient(grid, chunkGrad, chunks, grad);
  double loss = 0;
  for (double l : chunkLoss) loss += l;
  return loss / double(M);
}

double softBoxLossReference(std::span<const Point2> points, std::span<const Box2> boxes,
                            std::span<const double> masses, double alpha, std::span<Point2> grad) {
  validate(points, boxes, masses);
  const std::size_t N = points.size(), M = boxes.size();
  if (!grad.empty() && grad.size() != N)
    throw std::invalid_argument("softBoxLossReference: gradient size differs from the point count");
  std::fill(grad.begin(), grad.end(), Point2{});
  if (M == 0) return 0;
  double loss = 0;
  for (std::size_t m = 0; m < M; ++m) {
    const Box2 &A = boxes[m];
    double soft = 0;
    for (const Point2 &p : points) {
      const double d = std::min({p.x - A.lo.x, A.hi.x - p.x, p.y - A.lo.y, A.hi.y - p.y});
      soft += safeSigmoid(alpha * d);
    }
    const double r = (N ? soft / double(N) : 0.0) - masses[m];
    loss += r * r;
    if (grad.empty()) continue;
    const double coef = 2.0 * alpha * r / (double(M) * double(N));
    for (std::size_t i = 0; i < N; ++i) {
      const Point2 &p = points[i];
      const double toLoX = p.x - A.lo.x, toHiX = A.hi.x - p.x;
      const double toLoY = p.y - A.lo.y, toHiY = A.hi.y - p.y;
      const double dX = std::min(toLoX, toHiX), dY = std::min(toLoY, toHiY);
      const double e = std::exp(-std::abs(alpha * std::min(dX, dY)));
      const double slope = coef * e / ((1 + e) * (1 + e));  // sigma' is even
      // d moves with the nearest side's coordinate, ties to lo x, hi x, lo y, hi y.
      if (dX <= dY)
        grad[i].x += toLoX <= toHiX ? slope : -slope;
      else
        grad[i].y += toLoY <= toHiY ? slope : -slope;
    }
  }
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
