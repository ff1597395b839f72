#include "sampler/metrics/cdf_field.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>

namespace nuld {

CdfField::CdfField(const Target &target, std::vector<double> xNodes, std::vector<double> yNodes)
    : xs_(std::move(xNodes)),
      ys_(std::move(yNodes)),
      cols_(int(xs_.size()) - 1),
      rows_(int(ys_.size()) - 1) {
  checkNodes();
  f_.resize(std::size_t(cols_ + 1) * (rows_ + 1));
  tbb::parallel_for(0, rows_ + 1, [&](int j) {
    for (int i = 0; i <= cols_; ++i) f_[idx(i, j)] = target.mass({{0, 0}, {xs_[i], ys_[j]}});
  });
  integrate();
}

CdfField::CdfField(std::vector<double> xNodes, std::vector<double> yNodes,
                   std::vector<double> nodeValues)
    : xs_(std::move(xNodes)),
      ys_(std::move(yNodes)),
      cols_(int(xs_.size()) - 1),
      rows_(int(ys_.size()) - 1),
      f_(std::move(nodeValues)) {
  checkNodes();
  if (f_.size() != std::size_t(cols_ + 1) * (rows_ + 1))
    throw std::invalid_argument("CdfField: node values do not match the grid");
  integrate();
}

void CdfField::checkNodes() const {
  if (cols_ < 1 || rows_ < 1) throw std::invalid_argument("CdfField: needs at least one cell");
}

void CdfField::integrate() {
  xCells_ = EdgeLocator(xs_);
  yCells_ = EdgeLocator(ys_);
  hx_.assign(f_.size(), 0.0);
  hy_.assign(f_.size(), 0.0);
  g_.assign(f_.size(), 0.0);
  for (int j = 0; j <= rows_; ++j)
    for (int i = 1; i <= cols_; ++i)
      hx_[idx(i, j)] =
          hx_[idx(i - 1, j)] + 0.5 * (xs_[i] - xs_[i - 1]) * (f_[idx(i - 1, j)] + f_[idx(i, j)]);
  // Row after row (each column's running sum, in memory order).
  for (int j = 1; j <= rows_; ++j)
    for (int i = 0; i <= cols_; ++i)
      hy_[idx(i, j)] =
          hy_[idx(i, j - 1)] + 0.5 * (ys_[j] - ys_[j - 1]) * (f_[idx(i, j - 1)] + f_[idx(i, j)]);
  // Cumulative integral: rows of cells, each cell the mean of its corners.
  for (int j = 1; j <= rows_; ++j) {
    double row = 0;
    for (int i = 1; i <= cols_; ++i) {
      row += (xs_[i] - xs_[i - 1]) * (ys_[j] - ys_[j - 1]) * 0.25 *
             (f_[idx(i - 1, j - 1)] + f_[idx(i, j - 1)] + f_[idx(i - 1, j)] + f_[idx(i, j)]);
      g_[idx(i, j)] = g_[idx(i, j - 1)] + row;
    }
  }
}

double CdfField::lineX(int j, double x) const {
  x = std::clamp(x, 0.0, 1.0);
  const int i = xCell(x);
  const double dx = xs_[i + 1] - xs_[i], s = (x - xs_[i]) / dx;
  return hx_[idx(i, j)] +
         dx * ((s - 0.5 * s * s) * f_[idx(i, j)] + 0.5 * s * s * f_[idx(i + 1, j)]);
}

double CdfField::lineY(int i, double y) const {
  y = std::clamp(y, 0.0, 1.0);
  const int j = yCell(y);
  const double dy = ys_[j + 1] - ys_[j], t = (y - ys_[j]) / dy;
  return hy_[idx(i, j)] +
         dy * ((t - 0.5 * t * t) * f_[idx(i, j)] + 0.5 * t * t * f_[idx(i, j + 1)]);
}

double CdfField::cumulative(double x, double y) const {
  x = std::clamp(x, 0.0, 1.0);
  y = std::clamp(y, 0.0, 1.0);
  const int i = xCell(x), j = yCell(y);
  const double dx = xs_[i + 1] - xs_[i], dy = ys_[j + 1] - ys_[j];
  const double s = (x - xs_[i]) / dx, t = (y - ys_[j]) / dy;
  // Integrals of the hat functions over [0, s]: (1 - u) -> s - s^2/2, u -> s^2/2.
  const double p0 = s - 0.5 * s * s, p1 = 0.5 * s * s, q0 = t - 0.5 * t * t, q1 = 0.5 * t * t;
  // Strips below and left of the cell are linear in the free coordinate.
  const double below = dx * (p0 * hy_[idx(i, j)] + p1 * hy_[idx(i + 1, j)]);
  const double left = dy * (q0 * hx_[idx(i, j)] + q1 * hx_[idx(i, j + 1)]);
  const double inside = dx * dy *
                        (p0 * q0 * f_[idx(i, j)] + p1 * q0 * f_[idx(i + 1, j)] +
                         p0 * q1 * f_[idx(i, j + 1)] + p1 * q1 * f_[idx(i + 1, j + 1)]);
  return g_[idx(i, j)] + below + left + inside;
}

double CdfField::value(double x, double y) const {
  x = std::clamp(x, 0.0, 1.0);
  y = std::clamp(y, 0.0, 1.0);
  const int i = xCell(x), j = yCell(y);
  const double s = (x - xs_[i]) / (xs_[i + 1] - xs_[i]), t = (y - ys_[j]) / (ys_[j + 1] - ys_[j]);
  return (1 - s) * (1 - t) * f_[idx(i, j)] + s * (1 - t) * f_[idx(i + 1, j)] +
         (1 - s) * t * f_[idx(i, j + 1)] + s * t * f_[idx(i + 1, j + 1)];
}

double CdfField::columnIntegral(double x, double y) const {
  x = std::clamp(x, 0.0, 1.0);
  const int i = xCell(x);
  const double s = (x - xs_[i]) / (xs_[i + 1] - xs_[i]);
  return (1 - s) * lineY(i, y) + s * lineY(i + 1, y);  // F~ is linear in x between columns
}

double CdfField::rowIntegral(double y, double x) const {
  y = std::clamp(y, 0.0, 1.0);
  const int j = yCell(y);
  const double t = (y - ys_[j]) / (ys_[j + 1] - ys_[j]);
  return (1 - t) * lineX(j, x) + t * lineX(j + 1, x);
}

double CdfField::rectIntegral(double x0, double x1, double y0, double y1) const {
  return cumulative(x1, y1) - cumulative(x0, y1) - cumulative(x1, y0) + cumulative(x0, y0);
}

}  // namespace nuld
