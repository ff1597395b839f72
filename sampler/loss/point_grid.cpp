#include "sampler/loss/point_grid.h"

#include <algorithm>
#include <cmath>

namespace nuld {

PointGrid::PointGrid(std::span<const Point2> points, std::span<const double> weights,
                     int cellsPerSide) {
  const std::size_t n = points.size();
  g_ = cellsPerSide > 0 ? cellsPerSide
                        : std::clamp(int(std::lround(std::sqrt(double(n) / 2.0))), 1, 2048);
  const std::size_t cells = std::size_t(g_) * g_;
  std::vector<std::uint32_t> cellOfPoint(n);
  start_.assign(cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t c = std::uint32_t(cellOf(points[i].y)) * g_ + cellOf(points[i].x);
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

int PointGrid::cellOf(double t) const {
  if (!(t > 0)) return 0;     // also catches NaN
  if (t >= 1) return g_ - 1;  // also infinite sides: never convert inf to int
  return std::min(int(t * g_), g_ - 1);
}

PointGrid::CellRange PointGrid::cellsInside(const Box2 &box) const {
  // Cell c spans [c/g, (c+1)/g]; it is inside when c/g >= lo and (c+1)/g <= hi.
  auto first = [&](double lo) { return lo <= 0 ? 0 : int(std::ceil(std::min(lo, 2.0) * g_)); };
  auto last = [&](double hi) {
    return hi >= 1 ? g_ - 1 : int(std::floor(std::max(hi, -1.0) * g_)) - 1;
  };
  return {first(box.lo.x), last(box.hi.x), first(box.lo.y), last(box.hi.y)};
}

PointGrid::CellRange PointGrid::cellsTouching(const Box2 &box) const {
  if (box.lo.x > 1 || box.lo.y > 1 || box.hi.x < 0 || box.hi.y < 0 || box.lo.x > box.hi.x ||
      box.lo.y > box.hi.y)
    return {0, -1, 0, -1};
  return {cellOf(box.lo.x), cellOf(box.hi.x), cellOf(box.lo.y), cellOf(box.hi.y)};
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
