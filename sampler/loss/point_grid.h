#pragma once
// A grid over the unit square that buckets (optionally weighted) points, with
// a prefix table of per-cell totals. Cell edges sit at the quantiles of the
// points' coordinates, so clustered points (a target's dense regions) still
// get about two points per cell row and column. It answers "how much lies
// in this box" by summing whole cells from the prefix table and testing only
// the points of cells the box boundary crosses. The soft box loss uses it to
// visit only the band of points near a box's boundary; Monte Carlo mass
// estimation uses it to sum sample weights per box.

#include <cstdint>
#include <span>
#include <vector>

#include "sampler/point.h"
#include "sampler/targets/edge_locator.h"

namespace nuld {

class PointGrid {
 public:
  // `cellsPerSide` 0 picks about two points per cell.
  // `columnOrder` also builds the column-major copy (the soft loss scans
  // vertical bands in it; box sums do not need it).
  explicit PointGrid(std::span<const Point2> points, std::span<const double> weights = {},
                     int cellsPerSide = 0, bool columnOrder = false);

  int resolution() const { return g_; }
  std::size_t size() const { return index_.size(); }

  // Cells [cx0, cx1] x [cy0, cy1] (inclusive) whose extent lies entirely
  // inside `box`; empty (cx0 > cx1 or cy0 > cy1) when none does.
  struct CellRange {
    int cx0, cx1, cy0, cy1;
    bool empty() const { return cx0 > cx1 || cy0 > cy1; }
  };
  CellRange cellsInside(const Box2 &box) const;    // cells fully inside
  CellRange cellsTouching(const Box2 &box) const;  // cells that overlap

  // Sum of weights (or count) over a rectangle of whole cells.
  double cellSum(const CellRange &r) const;

  // Sorted storage: the points of cell (cx, cy) are the indices
  // [cellBegin(cx, cy), cellBegin(cx + 1, cy)) — cells of a row are contiguous.
  std::uint32_t cellBegin(int cx, int cy) const { return start_[std::size_t(cy) * g_ + cx]; }
  std::uint32_t rowEnd(int cx1, int cy) const { return start_[std::size_t(cy) * g_ + cx1 + 1]; }
  // Coordinates in this order, followed by kSlack readable zeros so that
  // vector loads may run past the last point.
  static constexpr std::size_t kSlack = 8;
  const double *xs() const { return xs_.data(); }
  const double *ys() const { return ys_.data(); }
  const std::vector<double> &weights() const { return w_; }  // empty when unweighted
  const std::vector<std::uint32_t> &originalIndex() const { return index_; }

  // Column-major storage of the same points: the points of cells
  // (cx, cy0..cy1) are [columnBegin(cx, cy0), columnEnd(cx, cy1)).
  std::uint32_t columnBegin(int cx, int cy) const { return colStart_[std::size_t(cx) * g_ + cy]; }
  std::uint32_t columnEnd(int cx, int cy1) const {
    return colStart_[std::size_t(cx) * g_ + cy1 + 1];
  }
  const double *columnXs() const { return colXs_.data(); }  // with kSlack zeros too
  const double *columnYs() const { return colYs_.data(); }
  const std::vector<std::uint32_t> &columnIndex() const { return colIndex_; }

  // Exact total (weight) of the points inside the closed box.
  double boxSum(const Box2 &box) const;

 private:
  void buildColumnOrder(const std::vector<std::uint32_t> &cellOfPoint,
                        std::span<const Point2> points);
  int cellOfX(double t) const { return xCells_.cell(xEdges_, t); }
  int cellOfY(double t) const { return yCells_.cell(yEdges_, t); }

  int g_;
  std::vector<double> xEdges_, yEdges_;  // g + 1 each, covering [0, 1] and every point
  EdgeLocator xCells_, yCells_;
  std::vector<std::uint32_t> start_;  // g*g + 1
  std::vector<double> xs_, ys_, w_;
  std::vector<std::uint32_t> index_;
  std::vector<std::uint32_t> colStart_, colIndex_;
  std::vector<double> colXs_, colYs_;
  std::vector<double> prefix_;  // (g+1)^2 inclusive prefix sums
};

}  // namespace nuld
