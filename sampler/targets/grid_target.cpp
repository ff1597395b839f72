#include "sampler/targets/grid_target.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "sampler/io/round_trip.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace nuld {
namespace {

// Guide tables (Chen & Asau 1974) over a nondecreasing CDF on [0, 1] with
// `cells` + 1 values: the answer for u is what upper_bound(cdf, u) - 1,
// clamped to [0, cells - 1], gives, found by starting at a lower bound kept
// per bucket of u and walking forward. Buckets are uniform in u, so the
// expected walk is about cells / buckets steps, and a lookup touches two or
// three cache lines instead of the ~log2(cells) of a binary search (the
// binary searches were a seventh of a render's time). The answer is exactly
// the binary search's, so sampling is unchanged bit for bit.
// (NaN goes to bucket 0 rather than to an index out of range.)
int bucketOf(double u, int buckets) { return u > 0 ? std::min(int(u * buckets), buckets - 1) : 0; }

// start[b]: the last j with bucketOf(cdf[j]) < b, or 0. For any u in bucket
// b, such a j has cdf[j] < u (rounding is monotone), so start[b] never
// passes the answer.
void buildGuide(const double *cdf, int cells, int buckets, std::uint32_t *start) {
  int j = 0;
  for (int b = 0; b < buckets; ++b) {
    while (j < cells - 1 && bucketOf(cdf[j + 1], buckets) < b) ++j;
    start[b] = std::uint32_t(j);
  }
}

int findInGuide(const double *cdf, int cells, int buckets, const std::uint32_t *start, double u) {
  int j = int(start[bucketOf(u, buckets)]);
  while (j < cells - 1 && cdf[j + 1] <= u) ++j;
  return j;
}

}  // namespace

void adviseHugePages(void *data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // Only whole 2 MiB pages inside the buffer; smaller tables gain nothing.
  constexpr std::uintptr_t kHuge = std::uintptr_t(2) << 20;
  const auto begin = (reinterpret_cast<std::uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(kHuge - 1);
  if (end > begin) madvise(reinterpret_cast<void *>(begin), end - begin, MADV_HUGEPAGE);
#endif
}

std::vector<double> GridTarget::uniformEdges(int cells) {
  std::vector<double> e(cells + 1);
  for (int i = 0; i <= cells; ++i) e[i] = double(i) / cells;
  e[cells] = 1.0;
  return e;
}

std::string GridTarget::contentHash() const {
  return ContentHash()
      .add("grid:")
      .add(std::string_view(spec_).substr(0, spec_.find(':')))
      .add(std::uint64_t(domain_))
      .add(std::span<const double>(xEdges_))
      .add(std::span<const double>(yEdges_))
      .add(std::span<const double>(density_))
      .hex();
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

  // Cell masses, validated, then normalized. Densities are scale-free: far
  // from 1 they are divided by the largest first, so tiny ones (an image of
  // 1e-300s) keep their ratios and huge ones do not overflow the sums
  // (ordinary ones are kept as given, bit for bit); a largest below the
  // normal doubles is refused.
  double largest = 0;
  for (int j = 0; j < rows_; ++j)
    for (int i = 0; i < cols_; ++i) {
      const double d = density[std::size_t(j) * cols_ + i];
      if (!std::isfinite(d) || d < 0)
        throw std::invalid_argument(source + ": cell (" + std::to_string(i) + ", " +
                                    std::to_string(j) + ") has density " + std::to_string(d) +
                                    "; expected a finite value >= 0");
      largest = std::max(largest, d);
    }
  if (largest > 0 && largest < std::numeric_limits<double>::min())
    throw std::invalid_argument(source + ": the largest density, " + formatRoundTrip(largest) +
                                ", underflows (below 2.2e-308); only ratios matter, so scale "
                                "the values up");
  const double scale = largest > 0 && (largest < 1e-100 || largest > 1e100) ? largest : 1.0;
  std::vector<double> cellMass(density.size());
  double total = 0;
  for (int j = 0; j < rows_; ++j)
    for (int i = 0; i < cols_; ++i) {
      const double d = density[std::size_t(j) * cols_ + i] / scale;
      const double m = d * (xEdges_[i + 1] - xEdges_[i]) * (yEdges_[j + 1] - yEdges_[j]);
      cellMass[std::size_t(j) * cols_ + i] = m;
      total += m;
    }
  if (!(total > 0) || !std::isfinite(total))
    throw std::invalid_argument(source + ": the density is zero everywhere (no mass to sample)");
  density_.resize(density.size());
  for (std::size_t k = 0; k < density.size(); ++k) {
    density_[k] = density[k] / scale / total;
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
  satLastColumn_.resize(rows_ + 1);
  for (int j = 0; j <= rows_; ++j) satLastColumn_[j] = sat_[std::size_t(j) * W + cols_];

  // Sampling tables: rows by their mass, then columns within the row.
  rowCdf_.assign(rows_ + 1, 0.0);
  reserveLargeTable(colCdf_, std::size_t(rows_) * W);
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

  // The row guide is small and always in cache: one bucket per row, a walk
  // of about one step. Each row's column guide has one bucket per four
  // columns (a walk of about two steps within one or two cache lines): a
  // quarter of the footprint, which on a large map matters more.
  rowGuide_.resize(rows_);
  buildGuide(rowCdf_.data(), rows_, rows_, rowGuide_.data());
  colBuckets_ = std::max(1, cols_ / 4);
  reserveLargeTable(colGuide_, std::size_t(rows_) * colBuckets_);
  colGuide_.resize(std::size_t(rows_) * colBuckets_);
  for (int j = 0; j < rows_; ++j)
    buildGuide(&colCdf_[std::size_t(j) * W], cols_, colBuckets_,
               &colGuide_[std::size_t(j) * colBuckets_]);
}

double GridTarget::pdf(Point2 p) const {
  if (!inUnitSquare(p)) return 0;
  return cellDensity(xCells_.cell(xEdges_, p.x), yCells_.cell(yEdges_, p.y));
}

double GridTarget::cumulative(double x, double y) const {
  x = std::clamp(x, 0.0, 1.0);
  y = std::clamp(y, 0.0, 1.0);
  // On the square's right or top side the mass is linear in the other
  // coordinate within a cell: one 1D table, no 2D read.
  const int W = cols_ + 1;
  if (x == 1.0) {
    const int j = yCells_.cell(yEdges_, y);
    const double ty = (y - yEdges_[j]) / (yEdges_[j + 1] - yEdges_[j]);
    return satLastColumn_[j] + ty * (satLastColumn_[j + 1] - satLastColumn_[j]);
  }
  if (y == 1.0) {
    const int i = xCells_.cell(xEdges_, x);
    const double tx = (x - xEdges_[i]) / (xEdges_[i + 1] - xEdges_[i]);
    const double *top = &sat_[std::size_t(rows_) * W];
    return top[i] + tx * (top[i + 1] - top[i]);
  }
  const int i = xCells_.cell(xEdges_, x), j = yCells_.cell(yEdges_, y);
  const double tx = (x - xEdges_[i]) / (xEdges_[i + 1] - xEdges_[i]);
  const double ty = (y - yEdges_[j]) / (yEdges_[j + 1] - yEdges_[j]);
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

// Inline, so that the batch form, which drops the Jacobian, also drops the
// reads and divisions only the Jacobian needs.
[[gnu::always_inline]] inline GridTarget::InRow GridTarget::invertInRow(Point2 u, int j) const {
  const double ux = u.x, uy = u.y;
  const double rowMass = rowCdf_[j + 1] - rowCdf_[j];
  const double ty = std::clamp((uy - rowCdf_[j]) / rowMass, 0.0, 1.0);
  const double y = yEdges_[j] + ty * (yEdges_[j + 1] - yEdges_[j]);

  const int W = cols_ + 1;
  const double *cdf = &colCdf_[std::size_t(j) * W];
  int i = findInGuide(cdf, cols_, colBuckets_, &colGuide_[std::size_t(j) * colBuckets_], ux);
  while (i > 0 && cdf[i + 1] <= cdf[i]) --i;
  const double cellFraction = cdf[i + 1] - cdf[i];
  const double tx = std::clamp((ux - cdf[i]) / cellFraction, 0.0, 1.0);
  const double x = xEdges_[i] + tx * (xEdges_[i + 1] - xEdges_[i]);
  return {{x, y}, {i, j}, cellFraction, rowMass};
}

Point2 GridTarget::primaryOf(Point2 x) const {
  const Cell c = locate(clampedUnit(x));
  const int i = c.i, j = c.j;
  const double ty = std::clamp((x.y - yEdges_[j]) / (yEdges_[j + 1] - yEdges_[j]), 0.0, 1.0);
  const double tx = std::clamp((x.x - xEdges_[i]) / (xEdges_[i + 1] - xEdges_[i]), 0.0, 1.0);
  const double *cdf = &colCdf_[std::size_t(j) * (cols_ + 1)];
  return clampedUnit(
      {cdf[i] + tx * (cdf[i + 1] - cdf[i]), rowCdf_[j] + ty * (rowCdf_[j + 1] - rowCdf_[j])});
}

Inversion GridTarget::invert(Point2 u) const {
  const Point2 c = clampedUnit(u);
  const InRow r = invertInRow(c, rowOf(c.y));
  const int i = r.cell.i, j = r.cell.j;
  Inversion out;
  out.x = r.x;
  // Within a cell the map is affine; the conditional does not depend on y
  // inside a row, so the Jacobian is diagonal.
  out.jacobian.m[0][0] = (xEdges_[i + 1] - xEdges_[i]) / r.cellFraction;
  out.jacobian.m[1][1] = (yEdges_[j + 1] - yEdges_[j]) / r.rowMass;
  return out;
}

GridTarget::Draw GridTarget::draw(Point2 u) const {
  const Point2 c = clampedUnit(u);
  const InRow r = invertInRow(c, rowOf(c.y));
  const int i = r.cell.i, j = r.cell.j;
  const double area = (xEdges_[i + 1] - xEdges_[i]) * (yEdges_[j + 1] - yEdges_[j]);
  return {r.x, r.cell, r.rowMass * r.cellFraction / area};
}

void GridTarget::invert(std::span<const Point2> u, std::span<Point2> x,
                        std::span<Cell> cells) const {
  // In groups: every point's row (small, hot tables) and the address of its
  // guide entry, prefetched; then the conditional CDF entry each guide entry
  // points to, prefetched; then the inversions proper. The points' cache
  // misses overlap instead of queueing one after another.
  constexpr std::size_t kGroup = 16;
  const int W = cols_ + 1;
  for (std::size_t first = 0; first < u.size(); first += kGroup) {
    const std::size_t n = std::min(kGroup, u.size() - first);
    Point2 c[kGroup];
    int row[kGroup];
    const std::uint32_t *guide[kGroup];
    for (std::size_t k = 0; k < n; ++k) {
      c[k] = clampedUnit(u[first + k]);
      row[k] = rowOf(c[k].y);
      guide[k] = &colGuide_[std::size_t(row[k]) * colBuckets_ + bucketOf(c[k].x, colBuckets_)];
      __builtin_prefetch(guide[k]);
    }
    for (std::size_t k = 0; k < n; ++k)
      __builtin_prefetch(&colCdf_[std::size_t(row[k]) * W + *guide[k]]);
    for (std::size_t k = 0; k < n; ++k) {
      const InRow r = invertInRow(c[k], row[k]);
      x[first + k] = r.x;
      cells[first + k] = r.cell;
    }
  }
}

Point2 GridTarget::clampedUnit(Point2 u) {
  return {std::clamp(u.x, 0.0, std::nextafter(1.0, 0.0)),
          std::clamp(u.y, 0.0, std::nextafter(1.0, 0.0))};
}

int GridTarget::rowOf(double uy) const {
  // The first row whose CDF range contains uy; zero-mass rows have an empty
  // range and are never chosen.
  int j = findInGuide(rowCdf_.data(), rows_, rows_, rowGuide_.data(), uy);
  while (j > 0 && rowCdf_[j + 1] <= rowCdf_[j]) --j;  // only when uy sits on the top edge
  return j;
}

}  // namespace nuld
