#pragma once
// A piecewise-constant density on a rectilinear grid over the unit square
// (cell edges need not be uniform: an environment map's rows are uneven in
// the equal-area v). Mass is exact through a summed-area table: inside a cell
// the mass is uniform, so the CDF at any point is a bilinear read of the table.
// Images, environment maps and tabulated BRDF lobes are all grid targets.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sampler/targets/edge_locator.h"
#include "sampler/targets/target.h"

namespace nuld {

// Reserves room for n elements in an empty vector and, on Linux, asks for
// transparent huge pages behind it before anything touches it. The sampling
// tables of a large map are read at random: with 4 KiB pages nearly every
// read also misses the TLB.
void adviseHugePages(void *data, std::size_t bytes);
template <typename T>
void reserveLargeTable(std::vector<T> &v, std::size_t n) {
  v.reserve(n);
  adviseHugePages(v.data(), n * sizeof(T));
}

class GridTarget final : public Target {
 public:
  // `density[j * cols + i]` is the (unnormalized) density of the cell
  // [xEdges[i], xEdges[i+1]] x [yEdges[j], yEdges[j+1]]. Edges run from 0 to
  // 1, strictly increasing. Densities must be finite, >= 0, not all zero;
  // `source` names where they came from for error messages.
  GridTarget(std::vector<double> xEdges, std::vector<double> yEdges,
             const std::vector<double> &density, std::string spec, Domain domain,
             const std::string &source);

  // Uniform cell edges.
  static std::vector<double> uniformEdges(int cells);

  // The normalized mass of [0, x_i] x [0, y_j] for every pair of edges, row
  // by row ((rows + 1) x (cols + 1)): the CDF at the grid's nodes, which
  // mass() returns there.
  const std::vector<double> &nodeCdf() const { return sat_; }

  std::string spec() const override { return spec_; }
  // The spec's family (the part before ':', naming e.g. the map's pixel
  // weight), the domain, the edges and the normalized densities.
  std::string contentHash() const override;
  Domain domain() const override { return domain_; }
  double pdf(Point2 p) const override;
  double mass(const Box2 &b) const override;
  Inversion invert(Point2 u) const override;

  // The cell (column i, row j) holding p, clamped to the grid.
  struct Cell {
    int i = 0, j = 0;
  };
  Cell locate(Point2 p) const { return {xCells_.cell(xEdges_, p.x), yCells_.cell(yEdges_, p.y)}; }
  // invert()'s point without its Jacobian, with the cell it landed in (so
  // callers with per-cell data, a map's radiance, need no second lookup)
  // and that cell's density, cellDensity() to rounding, from the masses the
  // inversion read (its mass over its area) rather than another table's
  // cache line.
  struct Draw {
    Point2 x;
    Cell cell;
    double density = 0;
  };
  Draw draw(Point2 u) const;
  // The inverse of invert(): the primary point u that invert() maps to x
  // (the Rosenblatt CDF map: the row's marginal CDF, then the column's
  // conditional CDF in that row, each linear within a cell). Exact for x in
  // a cell of positive density; a point in a zero-density cell maps to its
  // row's or cell's CDF value.
  Point2 primaryOf(Point2 x) const;
  // The points of invert(u[k], cells[k]) for every k into x[k], the same
  // values, without the Jacobians (an environment light needs only the
  // points and their cells). The table reads of the points overlap, which
  // is faster when the tables do not fit in cache (a large environment
  // map). Spans of equal size.
  void invert(std::span<const Point2> u, std::span<Point2> x, std::span<Cell> cells) const;

  int cols() const { return cols_; }
  const std::vector<double> &xEdges() const { return xEdges_; }
  const std::vector<double> &yEdges() const { return yEdges_; }
  int rows() const { return rows_; }
  // Normalized density of a cell (probability per unit area).
  double cellDensity(int i, int j) const { return density_[std::size_t(j) * cols_ + i]; }

 private:
  double cumulative(double x, double y) const;  // mass of [0,x] x [0,y]
  // invert() in steps: u clamped to [0,1), its row, the rest.
  static Point2 clampedUnit(Point2 u);
  int rowOf(double uy) const;
  // The point for u in row `row`, its cell, and the masses the Jacobian
  // divides by.
  struct InRow {
    Point2 x;
    Cell cell;
    double cellFraction, rowMass;
  };
  InRow invertInRow(Point2 u, int row) const;

  std::vector<double> xEdges_, yEdges_;
  EdgeLocator xCells_, yCells_;
  int cols_, rows_;
  std::vector<double> density_;  // normalized
  std::vector<double> sat_;      // (rows+1) x (cols+1): mass of [0,x_i] x [0,y_j]
  // Its last column, contiguous: mass of [0,1] x [0,y_j]. Most optimizer
  // boxes reach a side of the square, and a strided column read per box
  // cost a cache miss each.
  std::vector<double> satLastColumn_;
  std::vector<double> rowCdf_;  // rows+1: marginal CDF over rows
  std::vector<double> colCdf_;  // rows x (cols+1): conditional CDF in each row
  // Guide tables that make invert() O(1) on average (see grid_target.cpp):
  // rows buckets over rowCdf_, and cols buckets over each row of colCdf_.
  std::vector<std::uint32_t> rowGuide_;
  std::vector<std::uint32_t> colGuide_;
  int colBuckets_ = 1;
  std::string spec_;
  Domain domain_;
};

}  // namespace nuld
