#include "sampler/targets/grid_target.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nuld {

std::vector<double> GridTarget::uniformEdges(int cells) {
  std::vector<double> e(cells + 1);
  for (int i = 0; i <= cells; ++i) e[i] = double(i) / cells;
  e[cells] = 1.0;
  return e;
}

GridTarget::GridTarget(std::vector<double> xEdges, std::vector<double> yEdges,
                       const std::vector<double> &density, std::string spec, Domain domain,
                       const std::string &source)
    : xEdges_(std::move(xEdges)),
      yEdges_(std::move(yEdges)),
      cols_(int(xEdges_.size()) - 1),
      rows_(int(yEdges_.size()) - 1),
      spec_(std::move(spec)),
      domain_(domain) {
  auto checkEdges = [&](const std::vector<double> &e, const char *axis) {
    if (e.size() < 2 || e.front() != 0.0 || e.back() != 1.0)
      throw std::invalid_argument(source + ": " + axis + " cell edges must run from 0 to 1");
    for (std::size_t i = 1; i < e.size(); ++i)
      if (!(e[i] > e[i - 1]))
        throw std::invalid_argument(source + ": " + axis + " cell edges must increase");
  };
  checkEdges(xEdges_, "x");
  checkEdges(yEdges_, "y");
  xCells_ = EdgeLocator(xEdges_);
  yCells_ = EdgeLocator(yEdges_);
  if (density.size() != std::size_t(cols_) * rows_)
    throw std::invalid_argument(source + ": expected " + std::to_string(cols_ * rows_) +
                                " densities, got " + std::to_string(density.size()));

  // Cell masses, validated, then normalized.
  std::vector<double> cellMass(density.size());
  double total = 0;
  for (int j = 0; j < rows_; ++j)
    for (int i = 0; i < cols_; ++i) {
      const double d = density[std::size_t(j) * cols_ + i];
      if (!std::isfinite(d) || d < 0)
        throw std::invalid_argument(source + ": cell (" + std::to_string(i) + ", " +
                                    std::to_string(j) + ") has density " + std::to_string(d) +
                                    "; expected a finite value >= 0");
      const double m = d * (xEdges_[i + 1] - xEdges_[i]) * (yEdges_[j + 1] - yEdges_[j]);
      cellMass[std::size_t(j) * cols_ + i] = m;
      total += m;
    }
  if (!(total > 0) || !std::isfinite(total))
    throw std::invalid_argument(source + ": the density is zero everywhere (no mass to sample)");
  density_.resize(density.size());
  for (std::size_t k = 0; k < density.size(); ++k) {
    density_[k] = density[k] / total;
    cellMass[k] /= total;
  }

  // Summed-area table of cell masses.
  const int W = cols_ + 1;
  sat_.assign(std::size_t(rows_ + 1) * W, 0.0);
  for (int j = 0; j < rows_; ++j) {
    double rowSum = 0;
    for (int i = 0; i < cols_; ++i) {
      rowSum += cellMass[std::size_t(j) * cols_ + i];
      sat_[std::size_t(j + 1) * W + i + 1] = sat_[std::size_t(j) * W + i + 1] + rowSum;
    }
  }

  // Sampling tables: rows by their mass, then columns within the row.
  rowCdf_.assign(rows_ + 1, 0.0);
  colCdf_.assign(std::size_t(rows_) * W, 0.0);
  for (int j = 0; j < rows_; ++j) {
    double s = 0;
    for (int i = 0; i < cols_; ++i) {
      s += cellMass[std::size_t(j) * cols_ + i];
      colCdf_[std::size_t(j) * W + i + 1] = s;
    }
    rowCdf_[j + 1] = rowCdf_[j] + s;
    if (s > 0)
      for (int i = 1; i <= cols_; ++i) colCdf_[std::size_t(j) * W + i] /= s;
    colCdf_[std::size_t(j) * W + cols_] = s > 0 ? 1.0 : 0.0;
  }
  for (double &c : rowCdf_) c /= rowCdf_[rows_];
  rowCdf_[rows_] = 1.0;
}

double GridTarget::pdf(Point2 p) const {
  if (!(p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1)) return 0;
  return cellDensity(xCells_.cell(xEdges_, p.x), yCells_.cell(yEdges_, p.y));
}

double GridTarget::cumulative(double x, double y) const {
  x = std::clamp(x, 0.0, 1.0);
  y = std::clamp(y, 0.0, 1.0);
  const int i = xCells_.cell(xEdges_, x), j = yCells_.cell(yEdges_, y);
  const double tx = (x - xEdges_[i]) / (xEdges_[i + 1] - xEdges_[i]);
  const double ty = (y - yEdges_[j]) / (yEdges_[j + 1] - yEdges_[j]);
  const int W = cols_ + 1;
  const double s00 = sat_[std::size_t(j) * W + i], s10 = sat_[std::size_t(j) * W + i + 1];
  const double s01 = sat_[std::size_t(j + 1) * W + i], s11 = sat_[std::size_t(j + 1) * W + i + 1];
  // Exact: the mass inside one cell is uniform in area.
  return s00 + tx * (s10 - s00) + ty * (s01 - s00) + tx * ty * (s11 - s10 - s01 + s00);
}

double GridTarget::mass(const Box2 &box) const {
  const Box2 b = box.clipped();
  if (b.area() <= 0) return 0;
  // Corners on the lower edges of the square have zero cumulative mass:
  // multiple-corner boxes mostly need one or two table reads, not four.
  double m = cumulative(b.hi.x, b.hi.y);
  if (b.lo.x > 0) m -= cumulative(b.lo.x, b.hi.y);
  if (b.lo.y > 0) m -= cumulative(b.hi.x, b.lo.y);
  if (b.lo.x > 0 && b.lo.y > 0) m += cumulative(b.lo.x, b.lo.y);
  return std::max(0.0, m);
}

Inversion GridTarget::invert(Point2 u) const {
  Cell cell;
  return invert(u, cell);
}

Inversion GridTarget::invert(Point2 u, Cell &cell) const {
  const double uy = std::clamp(u.y, 0.0, std::nextafter(1.0, 0.0));
  const double ux = std::clamp(u.x, 0.0, std::nextafter(1.0, 0.0));
  // Row: the first row whose CDF range contains uy; zero-mass rows have an
  // empty range and are never chosen.
  int j = int(std::upper_bound(rowCdf_.begin(), rowCdf_.end(), uy) - rowCdf_.begin()) - 1;
  j = std::clamp(j, 0, rows_ - 1);
  while (j > 0 && rowCdf_[j + 1] <= rowCdf_[j]) --j;  // only when uy sits on the top edge
  const double rowMass = rowCdf_[j + 1] - rowCdf_[j];
  const double ty = std::clamp((uy - rowCdf_[j]) / rowMass, 0.0, 1.0);
  const double y = yEdges_[j] + ty * (yEdges_[j + 1] - yEdges_[j]);

  const int W = cols_ + 1;
  const double *cdf = &colCdf_[std::size_t(j) * W];
  int i = int(std::upper_bound(cdf, cdf + W, ux) - cdf) - 1;
  i = std::clamp(i, 0, cols_ - 1);
  while (i > 0 && cdf[i + 1] <= cdf[i]) --i;
  const double cellFrac = cdf[i + 1] - cdf[i];
  const double tx = std::clamp((ux - cdf[i]) / cellFrac, 0.0, 1.0);
  const double x = xEdges_[i] + tx * (xEdges_[i + 1] - xEdges_[i]);

  cell = {i, j};
  Inversion out;
  out.x = {x, y};
  // Within a cell the map is affine; the conditional does not depend on y
  // inside a row, so the Jacobian is diagonal.
  out.jacobian.m[0][0] = (xEdges_[i + 1] - xEdges_[i]) / cellFrac;
  out.jacobian.m[1][1] = (yEdges_[j + 1] - yEdges_[j]) / rowMass;
  return out;
}

}  // namespace nuld
