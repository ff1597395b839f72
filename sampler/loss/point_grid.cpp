#include "sampler/loss/point_grid.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>

namespace nuld {
namespace {

// Counting sort of item indices by key: items with key k end up in
// order[start[k] .. start[k + 1]), in their original order.
void bucketByKey(const std::vector<std::uint32_t> &key, std::size_t buckets,
                 std::vector<std::uint32_t> &start, std::vector<std::uint32_t> &order) {
  start.assign(buckets + 1, 0);
  for (std::uint32_t k : key) ++start[k + 1];
  for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  order.resize(key.size());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < key.size(); ++i) order[fill[key[i]]++] = std::uint32_t(i);
}

}  // namespace

PointGrid::PointGrid(std::span<const Point2> points, std::span<const double> weights,
                     int cellsPerSide, bool columnOrder) {
  const std::size_t n = points.size();
  g_ = cellsPerSide > 0 ? cellsPerSide
                        : std::clamp(int(std::lround(std::sqrt(double(n) / 2.0))), 1, 2048);
  const std::size_t cells = std::size_t(g_) * g_;
  // Quantile edges, halfway between neighbouring sorted coordinates.
  auto quantileEdges = [&](auto coordinate) {
    std::vector<double> c(n);
    for (std::size_t i = 0; i < n; ++i) c[i] = coordinate(points[i]);
    std::sort(c.begin(), c.end());
    std::vector<double> e(g_ + 1);
    e[0] = n ? std::min(0.0, c.front()) : 0.0;
    e[g_] = n ? std::max(1.0, c.back()) : 1.0;
    for (int k = 1; k < g_; ++k) {
      const std::size_t q = std::size_t(k) * n / g_;
      e[k] = std::clamp(0.5 * (c[q - 1] + c[q]), e[k - 1], e[g_]);
    }
    return e;
  };
  tbb::parallel_invoke([&] { xEdges_ = quantileEdges([](Point2 p) { return p.x; }); },
                       [&] { yEdges_ = quantileEdges([](Point2 p) { return p.y; }); });
  xCells_ = EdgeLocator(xEdges_);
  yCells_ = EdgeLocator(yEdges_);
  std::vector<std::uint32_t> cellOfPoint(n);
  for (std::size_t i = 0; i < n; ++i)
    cellOfPoint[i] = std::uint32_t(cellOfY(points[i].y)) * g_ + cellOfX(points[i].x);
  bucketByKey(cellOfPoint, cells, start_, index_);
  xs_.assign(n + kSlack, 0.0);
  ys_.assign(n + kSlack, 0.0);
  if (!weights.empty()) w_.resize(n);
  for (std::size_t slot = 0; slot < n; ++slot) {
    const std::uint32_t i = index_[slot];
    xs_[slot] = points[i].x;
    ys_[slot] = points[i].y;
    if (!weights.empty()) w_[slot] = weights[i];
  }
  // The same points in column-major cell order: a column of cells is then
  // one contiguous run (the band along a box's vertical side).
  if (columnOrder) buildColumnOrder(cellOfPoint, points);

  // Inclusive 2D prefix sums of cell totals.
  const int W = g_ + 1;
  prefix_.assign(std::size_t(W) * W, 0.0);
  for (int cy = 0; cy < g_; ++cy) {
    double row = 0;
    for (int cx = 0; cx < g_; ++cx) {
      const std::uint32_t b = cellBegin(cx, cy), e = start_[std::size_t(cy) * g_ + cx + 1];
      double total = 0;
      if (w_.empty())
        total = double(e - b);
      else
        for (std::uint32_t k = b; k < e; ++k) total += w_[k];
      row += total;
      prefix_[std::size_t(cy + 1) * W + cx + 1] = prefix_[std::size_t(cy) * W + cx + 1] + row;
    }
  }
}

void PointGrid::buildColumnOrder(const std::vector<std::uint32_t> &cellOfPoint,
                                 std::span<const Point2> points) {
  const std::size_t n = points.size();
  std::vector<std::uint32_t> columnCell(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t cx = cellOfPoint[i] % g_, cy = cellOfPoint[i] / g_;
    columnCell[i] = cx * g_ + cy;
  }
  bucketByKey(columnCell, std::size_t(g_) * g_, colStart_, colIndex_);
  colXs_.assign(n + kSlack, 0.0);
  colYs_.assign(n + kSlack, 0.0);
  for (std::size_t slot = 0; slot < n; ++slot) {
    colXs_[slot] = points[colIndex_[slot]].x;
    colYs_[slot] = points[colIndex_[slot]].y;
  }
}

PointGrid::CellRange PointGrid::cellsInside(const Box2 &box) const {
  // Cell c spans [e[c], e[c+1]]; it is inside when e[c] >= lo and e[c+1] <= hi.
  // The locator's cell holds the bound; step past it when it sticks out.
  const auto first = [](const std::vector<double> &e, const EdgeLocator &cells, double lo) {
    const int c = cells.cell(e, lo);
    return e[c] >= lo ? c : c + 1;
  };
  const auto last = [](const std::vector<double> &e, const EdgeLocator &cells, double hi) {
    const int c = cells.cell(e, hi);
    return e[c + 1] <= hi ? c : c - 1;
  };
  return {first(xEdges_, xCells_, box.lo.x), last(xEdges_, xCells_, box.hi.x),
          first(yEdges_, yCells_, box.lo.y), last(yEdges_, yCells_, box.hi.y)};
}

PointGrid::CellRange PointGrid::cellsTouching(const Box2 &box) const {
  if (box.lo.x > xEdges_.back() || box.lo.y > yEdges_.back() || box.hi.x < xEdges_.front() ||
      box.hi.y < yEdges_.front() || box.lo.x > box.hi.x || box.lo.y > box.hi.y)
    return {0, -1, 0, -1};
  return {cellOfX(box.lo.x), cellOfX(box.hi.x), cellOfY(box.lo.y), cellOfY(box.hi.y)};
}

double PointGrid::cellSum(const CellRange &r) const {
  if (r.empty()) return 0;
  const int W = g_ + 1;
  auto P = [&](int cx, int cy) { return prefix_[std::size_t(cy) * W + cx]; };
  return P(r.cx1 + 1, r.cy1 + 1) - P(r.cx0, r.cy1 + 1) - P(r.cx1 + 1, r.cy0) + P(r.cx0, r.cy0);
}

double PointGrid::boxSum(const Box2 &box) const {
  const CellRange touch = cellsTouching(box);
  if (touch.empty()) return 0;
  const CellRange in = cellsInside(box);
  double sum = cellSum(in);
  for (int cy = touch.cy0; cy <= touch.cy1; ++cy) {
    const bool rowInside = !in.empty() && cy >= in.cy0 && cy <= in.cy1;
    auto scan = [&](int cx0, int cx1) {
      if (cx0 > cx1) return;
      for (std::uint32_t k = cellBegin(cx0, cy), e = rowEnd(cx1, cy); k < e; ++k)
        if (box.contains({xs_[k], ys_[k]})) sum += w_.empty() ? 1.0 : w_[k];
    };
    if (rowInside) {
      scan(touch.cx0, in.cx0 - 1);
      scan(in.cx1 + 1, touch.cx1);
    } else {
      scan(touch.cx0, touch.cx1);
    }
  }
  return sum;
}

}  // namespace nuld
