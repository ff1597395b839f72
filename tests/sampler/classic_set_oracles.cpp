#include "tests/sampler/classic_set_oracles.h"

#include <cmath>

namespace nuld::test {

std::string netFailure(std::span<const Point2> pts, int m) {
  const std::size_t cells = std::size_t(1) << m;
  if (pts.size() != cells) return "not 2^" + std::to_string(m) + " points";
  std::vector<int> count(cells);
  for (int a = 0; a <= m; ++a) {
    std::fill(count.begin(), count.end(), 0);
    const double cols = std::ldexp(1.0, a), rows = std::ldexp(1.0, m - a);
    for (const Point2 &p : pts) {
      if (!(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1)) return "a point outside [0, 1)^2";
      const auto ix = std::size_t(std::floor(p.x * cols)), iy = std::size_t(std::floor(p.y * rows));
      ++count[iy * std::size_t(cols) + ix];
    }
    for (std::size_t c = 0; c < cells; ++c)
      if (count[c] != 1)
        return "shape 2^-" + std::to_string(a) + " x 2^-" + std::to_string(m - a) + ": cell " +
               std::to_string(c) + " holds " + std::to_string(count[c]) + " points";
  }
  return "";
}

std::string sequenceNetFailure(std::span<const Point2> pts, bool blocks) {
  for (int j = 0; (std::size_t(1) << j) <= pts.size(); ++j) {
    const std::size_t size = std::size_t(1) << j;
    for (std::size_t start = 0; start + size <= pts.size(); start += size) {
      if (const std::string why = netFailure(pts.subspan(start, size), j); !why.empty())
        return "points " + std::to_string(start) + ".." + std::to_string(start + size - 1) + ": " +
               why;
      if (!blocks) break;
    }
  }
  return "";
}

double chiSquareUniform(std::span<const int> counts) {
  double total = 0;
  for (int c : counts) total += c;
  const double expected = total / double(counts.size());
  double chi2 = 0;
  for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

double chiSquareCritical(int bins) {
  // Wilson-Hilferty: chi2_k ~ k (1 - 2/(9k) + z sqrt(2/(9k)))^3, z(0.999) = 3.0902.
  const double k = bins - 1, z = 3.090232;
  const double t = 1 - 2 / (9 * k) + z * std::sqrt(2 / (9 * k));
  return k * t * t * t;
}

MeanEstimate smoothIntegrandMean(const SetMaker &make, std::size_t n, int seeds) {
  const double exact = (std::exp(1.0) - 1) * 2 * (std::exp(0.5) - 1);
  std::vector<Point2> pts(n);
  double sum = 0, sumSq = 0;
  for (int s = 0; s < seeds; ++s) {
    make(std::uint64_t(s) * 0x9e3779b97f4a7c15ull + 12345, pts);
    double estimate = 0;
    for (const Point2 &p : pts) estimate += std::exp(p.x + 0.5 * p.y);
    estimate /= double(n);
    sum += estimate;
    sumSq += estimate * estimate;
  }
  const double mean = sum / seeds, var = std::max(0.0, sumSq / seeds - mean * mean);
  return {mean, std::sqrt(var / (seeds - 1)), exact};
}

}  // namespace nuld::test
