#pragma once
// The CDF F(a, b) = mu([0,a] x [0,b]) of a target, sampled at the nodes of a
// rectilinear grid and interpolated bilinearly (F~). Rectangle integrals of
// F~ and of its edge profiles F~(a, 1), F~(1, b) are exact in O(1) through
// cumulative tables. For a piecewise-constant target whose cells are the
// grid's cells F~ = F exactly (inside a cell the mass is uniform, so F is
// bilinear there); for smooth targets the error is O(h^2).

#include <vector>

#include "sampler/targets/edge_locator.h"
#include "sampler/targets/target.h"

namespace nuld {

class CdfField {
 public:
  CdfField(const Target &target, std::vector<double> xNodes, std::vector<double> yNodes);
  // From F at the nodes, row by row ((y nodes) x (x nodes)): a grid
  // target's own table, with no mass query per node.
  CdfField(std::vector<double> xNodes, std::vector<double> yNodes, std::vector<double> nodeValues);

  // Integral of F~ over [x0, x1] x [y0, y1] (inside the unit square).
  double rectIntegral(double x0, double x1, double y0, double y1) const;
  // Integral of F~(a, 1) over a in [0, x] and of F~(1, b) over b in [0, y].
  double topIntegral(double x) const { return lineX(rows_, x); }
  double rightIntegral(double y) const { return lineY(cols_, y); }

  // F~ itself, and its integrals along a vertical or horizontal line through
  // any point: int_0^y F~(x, b) db and int_0^x F~(a, y) da.
  double value(double x, double y) const;
  double columnIntegral(double x, double y) const;
  double rowIntegral(double y, double x) const;

  int cols() const { return cols_; }
  int rows() const { return rows_; }
  double xNode(int i) const { return xs_[i]; }
  double yNode(int j) const { return ys_[j]; }
  double node(int i, int j) const { return f_[idx(i, j)]; }

 private:
  std::size_t idx(int i, int j) const { return std::size_t(j) * (cols_ + 1) + i; }
  // Refuses a grid without a cell; integrate() fills the cell locators and
  // the integral tables from the node values f_.
  void checkNodes() const;
  void integrate();
  // The cell of x (of y) holding t: every integral and value the optimizer
  // asks for looks up its cells, tens of times per point and epoch.
  int xCell(double t) const { return xCells_.cell(xs_, t); }
  int yCell(double t) const { return yCells_.cell(ys_, t); }
  double cumulative(double x, double y) const;  // integral over [0,x] x [0,y]
  double lineX(int j, double x) const;          // integral of F~(a, y_j), a in [0, x]
  double lineY(int i, double y) const;          // integral of F~(x_i, b), b in [0, y]

  std::vector<double> xs_, ys_;
  EdgeLocator xCells_, yCells_;
  int cols_, rows_;
  std::vector<double> f_;   // node values
  std::vector<double> g_;   // integral over [0, x_i] x [0, y_j]
  std::vector<double> hx_;  // integral of F~(a, y_j) over a in [0, x_i]
  std::vector<double> hy_;  // integral of F~(x_i, b) over b in [0, y_j]
};

}  // namespace nuld
