#include "sampler/loss/point_grid.h"

#include <algorithm>
#include <cmath>

namespace nuld {

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
  xEdges_ = quantileEdges([](Point2 p) { return p.x; });
  yEdges_ = quantileEdges([](Point2 p) { return p.y; });
  xCells_ = EdgeLocator(xEdges_);
  yCells_ = EdgeLocator(yEdges_);
  std::vector<std::uint32_t> cellOfPoint(n);
  start_.assign(cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t c = std::uint32_t(cellOfY(points[i].y)) * g_ + cellOfX(points[i].x);
    cellOfPoint[i] = c;
    ++start_[c + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  xs_.resize(n);
  ys_.resize(n);
  index_.resize(n);
  if (!weights.empty()) w_.resize(n);
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t slot = fill[cellOfPoint[i]]++;
    xs_[slot] = points[i].x;
    ys_[slot] = points[i].y;
    index_[slot] = std::uint32_t(i);
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
  const std::size_t n = points.size(), cells = std::size_t(g_) * g_;
  colStart_.assign(cells + 1, 0);
  std::vector<std::uint32_t> colCell(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t c = cellOfPoint[i], cx = c % g_, cy = c / g_;
    colCell[i] = cx * g_ + cy;
    ++colStart_[colCell[i] + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) colStart_[c + 1] += colStart_[c];
  colXs_.resize(n);
  colYs_.resize(n);
  colIndex_.resize(n);
  std::vector<std::uint32_t> colFill(colStart_.begin(), colStart_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t slot = colFill[colCell[i]]++;
    colXs_[slot] = points[i].x;
    colYs_[slot] = points[i].y;
    colIndex_[slot] = std::uint32_t(i);
  }
}

PointGrid::CellRange PointGrid::cellsInside(const Box2 &box) const {
  // Cell c spans [e[c], e[c+1]]; it is inside when e[c] >= lo and e[c+1] <= hi.
  auto first = [](const std::vector<double> &e, double lo) {
    return int(std::lower_bound(e.begin(), e.end(), lo) - e.begin());
  };
  auto last = [](const std::vector<double> &e, double hi) {
    return int(std::upper_bound(e.begin(), e.end(), hi) - e.begin()) - 2;
  };
  return {first(xEdges_, box.lo.x), last(xEdges_, box.hi.x), first(yEdges_, box.lo.y),
          last(yEdges_, box.hi.y)};
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
