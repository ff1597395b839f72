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

// Which side of the box is nearest, as the sign of dd/dx along its axis.
enum Side : std::uint8_t { kLoX, kHiX, kLoY, kHiY };

struct BandEntry {
  std::uint32_t slot;  // the point's index in the caller's array
  Side side;
  double dsigma;  // sigma'(alpha d)
};

// Number of partial sums: a function of the problem size only, never of the
// thread count, so that results are bit-identical on any machine.
std::size_t chunkCount(std::size_t n, std::size_t m) {
  const std::size_t byBoxes = std::max<std::size_t>(1, m / 128);
  const std::size_t byMemory =
      std::max<std::size_t>(1, (std::size_t(1) << 22) / std::max<std::size_t>(n, 1));
  return std::min({byBoxes, byMemory, std::size_t(64)});
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
  const auto &xs = grid.xs();
  const auto &ys = grid.ys();
  const double invN = 1.0 / double(N);
  const double gradScale = 2.0 * alpha / (double(M) * double(N));

  const std::size_t chunks = chunkCount(N, M);
  std::vector<double> chunkLoss(chunks, 0.0);
  std::vector<Point2> chunkGrad(wantGrad ? chunks * N : 0);

  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    const std::size_t m0 = M * c / chunks, m1 = M * (c + 1) / chunks;
    Point2 *g = wantGrad ? &chunkGrad[c * N] : nullptr;
    std::vector<BandEntry> band;
    double lossSum = 0;
    for (std::size_t m = m0; m < m1; ++m) {
      const Box2 &A = boxes[m];
      const Box2 inner{{A.lo.x + delta, A.lo.y + delta}, {A.hi.x - delta, A.hi.y - delta}};
      const Box2 outer{{A.lo.x - delta, A.lo.y - delta}, {A.hi.x + delta, A.hi.y + delta}};
      const PointGrid::CellRange touch = grid.cellsTouching(outer);
      const PointGrid::CellRange in = grid.cellsInside(inner);
      double count = grid.cellSum(in);  // whole cells deep inside: sigma = 1
      double soft = 0;
      band.clear();

      // Evaluates the contiguous run [begin, end) of one storage order (xs,
      // ys, original indices) in branch-free, vectorizable blocks; only band
      // points (sigma' > 0) are kept for the gradient.
      auto scan = [&](const double *sx, const double *sy, const std::uint32_t *original,
                      std::uint32_t begin, std::uint32_t end) {
        constexpr int kBlock = 64;
        alignas(64) double value[kBlock], slope[kBlock];
        for (std::uint32_t k0 = begin; k0 < end; k0 += kBlock) {
          const int n = int(std::min<std::uint32_t>(kBlock, end - k0));
          const double *bx = sx + k0, *by = sy + k0;
          for (int j = 0; j < n; ++j) {
            const double d = std::min(std::min(bx[j] - A.lo.x, A.hi.x - bx[j]),
                                      std::min(by[j] - A.lo.y, A.hi.y - by[j]));
            const double at = alpha * d;
            const double a = std::min(std::abs(at), cutoff);
            const double e = fastExpNonPositive(-a);
            const double inv = 1 / (1 + e);
            const bool band = std::abs(at) <= cutoff;
            value[j] = at > cutoff ? 1.0 : band ? (at >= 0 ? inv : e * inv) : 0.0;
            slope[j] = band ? e * inv * inv : 0.0;
          }
          double partial[4] = {0, 0, 0, 0};
          for (int j = 0; j < n; ++j) partial[j & 3] += value[j];
          soft += (partial[0] + partial[1]) + (partial[2] + partial[3]);
          if (!wantGrad) continue;
          for (int j = 0; j < n; ++j) {
            if (slope[j] == 0) continue;
            const double x = bx[j], y = by[j];
            double d = x - A.lo.x;
            Side side = kLoX;
            if (const double t = A.hi.x - x; t < d) {
              d = t;
              side = kHiX;
            }
            if (const double t = y - A.lo.y; t < d) {
              d = t;
              side = kLoY;
            }
            if (const double t = A.hi.y - y; t < d) side = kHiY;
            band.push_back({original[k0 + j], side, slope[j]});
          }
        }
      };
      const double *rx = xs.data(), *ry = ys.data(), *cx = grid.columnXs().data(),
                   *cy = grid.columnYs().data();
      const std::uint32_t *ri = grid.originalIndex().data(), *ci = grid.columnIndex().data();
      if (!touch.empty()) {
        if (in.empty()) {
          for (int row = touch.cy0; row <= touch.cy1; ++row)
            scan(rx, ry, ri, grid.cellBegin(touch.cx0, row), grid.rowEnd(touch.cx1, row));
        } else {
          // Rows above and below the interior: whole rows of the touched range.
          for (int row = touch.cy0; row < in.cy0; ++row)
            scan(rx, ry, ri, grid.cellBegin(touch.cx0, row), grid.rowEnd(touch.cx1, row));
          for (int row = in.cy1 + 1; row <= touch.cy1; ++row)
            scan(rx, ry, ri, grid.cellBegin(touch.cx0, row), grid.rowEnd(touch.cx1, row));
          // Columns left and right of the interior, over the interior's rows:
          // one contiguous run each in the column-major order.
          for (int col = touch.cx0; col < in.cx0; ++col)
            scan(cx, cy, ci, grid.columnBegin(col, in.cy0), grid.columnEnd(col, in.cy1));
          for (int col = in.cx1 + 1; col <= touch.cx1; ++col)
            scan(cx, cy, ci, grid.columnBegin(col, in.cy0), grid.columnEnd(col, in.cy1));
        }
      }

      const double r = (count + soft) * invN - masses[m];
      lossSum += r * r;
      if (wantGrad && r != 0) {
        const double coef = gradScale * r;
        for (const BandEntry &b : band) {
          const double v = coef * b.dsigma;
          switch (b.side) {
            case kLoX: g[b.slot].x += v; break;
            case kHiX: g[b.slot].x -= v; break;
            case kLoY: g[b.slot].y += v; break;
            case kHiY: g[b.slot].y -= v; break;
          }
        }
      }
    }
    chunkLoss[c] = lossSum;
  });

  if (wantGrad) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 1024), [&](const auto &r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i) {
        Point2 sum{};
        for (std::size_t c = 0; c < chunks; ++c) sum = sum + chunkGrad[c * N + i];
        grad[i] = sum;
      }
    });
  }
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
