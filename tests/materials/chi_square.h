#pragma once
// Chi-square goodness-of-fit of a direction sampler against its claimed pdf,
// the pbrt-v4 / Mitsuba way: histogram the sampled directions on the
// equal-area hemisphere (u = phi / 2 pi, v = (1 - cos theta) / 2 in [0, 1/2]),
// integrate the pdf over every bin for the expected counts, count the
// failures (nullopt) against the mass the pdf leaves out, pool bins expected
// below 5, and compare the statistic with a Sidak-corrected significance.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "materials/sphere_map.h"
#include "materials/vec3.h"
#include "sampler/sequences/rng.h"
#include "tests/common/chi_square.h"
#include "tests/materials/quadrature.h"

namespace nuld::test {

// Upper bound on the number of chi-square tests in the materials suite (about
// 115: the Disney sampling cases under four choices, the dielectric cases in
// both forms, the microfacet, target and Lambertian ones); each
// runs at the Sidak-corrected level, so the whole suite fails by chance with
// probability at most 1 %.
inline constexpr int kChiSquareTests = 128;
inline double sidakLevel(double overall = 0.01) { return sidakLevel(overall, kChiSquareTests); }

// A third uniform number for a sampler of the square that also draws a lobe
// choice (Bsdf::sample's uc): a hash of u's bits, independent of u for any
// test's purposes.
inline double choiceOf(Point2 u) {
  return toUnitDouble(
      hashCombine(std::bit_cast<std::uint64_t>(u.x), std::bit_cast<std::uint64_t>(u.y)));
}

// A direction sampler (nullopt: no sample) and the pdf it claims, per unit
// solid angle.
using DirectionSampler = std::function<std::optional<Vec3>(Point2)>;
using DirectionPdf = std::function<double(Vec3)>;

struct DirectionTest {
  ChiSquare chi;
  double pdfMass = 0;         // integral of the pdf over the hemisphere
  double failedFraction = 0;  // nullopt samples / samples
  double belowFraction = 0;   // samples returned below the horizon (never allowed)
  std::string describe() const {
    std::ostringstream s;
    s << "chi^2 = " << chi.statistic << ", dof " << chi.dof << ", p = " << chi.pValue
      << ", pdf mass " << pdfMass << ", failed " << failedFraction << " " << chi.note;
    return s.str();
  }
};

// Mesh grading for a lobe peaking at the direction `w`, and always toward
// the pole v = 0, where functions of direction vary like sqrt(v) on the
// square. A peak at the pole spans every u, so it is graded in v only.
inline Peak peakAt(std::optional<Vec3> w = std::nullopt) {
  Peak peak{{}, {0.0}};
  if (!w) return peak;
  const Point2 p = spherePoint(normalize(*w));
  if (p.y < 1e-9) return peak;
  peak.x.push_back(p.x);
  peak.y.push_back(p.y);
  return peak;
}

// Bins: `cols` in phi, `rows` in v over the upper hemisphere (or, for a
// sampler that transmits, `wholeSphere`, the whole sphere: v in [0, 1]),
// plus one bin for failed samples expected to hold n (1 - pdf mass).
inline DirectionTest testDirections(const DirectionSampler &sample, const DirectionPdf &pdf, int n,
                                    std::uint64_t seed, const Peak &peak = peakAt(), int cols = 80,
                                    int rows = 40, bool wholeSphere = false) {
  const double vMax = wholeSphere ? 1.0 : 0.5;
  const auto xEdges = uniformEdges(0, 1, cols), yEdges = uniformEdges(0, vMax, rows);
  const std::size_t bins = std::size_t(cols) * rows;
  std::vector<double> observed(bins + 1, 0.0), expected(bins + 1, 0.0);
  Rng rng(seed);
  DirectionTest t;
  int below = 0;
  for (int s = 0; s < n; ++s) {
    const Point2 u{rng.uniform(), rng.uniform()};
    const auto w = sample(u);
    if (!w) {
      observed[bins] += 1;
      continue;
    }
    if (!(w->z > 0) && !wholeSphere) {
      ++below;
      continue;
    }
    const Point2 p = spherePoint(*w);
    const int i = std::min(cols - 1, int(p.x * cols));
    const int j = std::min(rows - 1, int(p.y / vMax * rows));
    observed[std::size_t(j) * cols + i] += 1;
  }
  // Density on the square = density per steradian * 4 pi (equal-area map).
  const auto cells =
      integrateCells([&](Point2 p) { return 4 * std::numbers::pi * pdf(sphereDirection(p)); },
                     xEdges, yEdges, peak);
  for (std::size_t k = 0; k < bins; ++k) {
    expected[k] = n * cells[k];
    t.pdfMass += cells[k];
  }
  expected[bins] = n * std::max(0.0, 1 - t.pdfMass);
  t.failedFraction = observed[bins] / n;
  t.belowFraction = double(below) / n;
  t.chi = pooledChiSquare(observed, expected);
  return t;
}

}  // namespace nuld::test
