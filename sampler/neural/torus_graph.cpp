#include "sampler/neural/torus_graph.h"

#include <algorithm>
#include <cmath>

namespace nuld {

Point2 torusDifference(Point2 a, Point2 b) {
  auto wrap = [](double d) { return d - std::floor(d + 0.5); };
  return {wrap(b.x - a.x), wrap(b.y - a.y)};
}

TorusGraph buildTorusGraph(std::span<const Point2> points, std::size_t k) {
  TorusGraph g;
  g.n = points.size();
  g.k = g.n == 0 ? 0 : std::min(k, g.n - 1);
  if (g.k == 0) return g;
  std::vector<Point2> p(points.begin(), points.end());
  for (Point2 &q : p) q = {wrapUnit(q.x), wrapUnit(q.y)};

  // Buckets of side 1 / res with about one point each.
  const int res = std::max(1, int(std::sqrt(double(g.n))));
  auto cellOf = [res](double t) { return std::min(res - 1, int(t * res)); };
  std::vector<std::vector<std::int64_t>> cells(std::size_t(res) * res);
  for (std::size_t i = 0; i < g.n; ++i)
    cells[std::size_t(cellOf(p[i].y)) * res + cellOf(p[i].x)].push_back(std::int64_t(i));

  g.neighbours.resize(g.n * g.k);
  g.offsets.resize(g.n * g.k);
  std::vector<std::pair<double, std::int64_t>> found;
  for (std::size_t i = 0; i < g.n; ++i) {
    const int cx = cellOf(p[i].x), cy = cellOf(p[i].y);
    found.clear();
    // Ring r holds the cells at Chebyshev distance r from i's cell; every
    // point beyond ring r is at least r / res away, so once k points lie
    // within that, the search is complete. Once a ring would wrap onto
    // cells already visited, every point is taken instead.
    for (int r = 0;; ++r) {
      if (2 * r + 1 >= res) {
        found.clear();
        for (std::size_t j = 0; j < g.n; ++j) {
          if (j == i) continue;
          const Point2 d = torusDifference(p[i], p[j]);
          found.push_back({d.x * d.x + d.y * d.y, std::int64_t(j)});
        }
        break;
      }
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          if (std::max(std::abs(dx), std::abs(dy)) != r) continue;
          const int x = (cx + dx + res) % res, y = (cy + dy + res) % res;
          for (std::int64_t j : cells[std::size_t(y) * res + x]) {
            if (std::size_t(j) == i) continue;
            const Point2 d = torusDifference(p[i], p[std::size_t(j)]);
            found.push_back({d.x * d.x + d.y * d.y, j});
          }
        }
      if (found.size() >= g.k) {
        std::nth_element(found.begin(), found.begin() + std::ptrdiff_t(g.k - 1), found.end());
        const double reach = double(r) / res;
        if (found[g.k - 1].first <= reach * reach) break;
      }
    }
    std::sort(found.begin(), found.end());
    for (std::size_t j = 0; j < g.k; ++j) {
      g.neighbours[i * g.k + j] = found[j].second;
      g.offsets[i * g.k + j] = torusDifference(p[i], p[std::size_t(found[j].second)]);
    }
  }
  return g;
}

}  // namespace nuld
