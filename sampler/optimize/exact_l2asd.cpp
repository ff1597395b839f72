#include "sampler/optimize/exact_l2asd.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace nuld {

double l2asdSquaredWithGradient(std::span<const Point2> p, std::span<Point2> grad) {
  const std::size_t n = p.size();
  if (n == 0) throw std::invalid_argument("l2asd objective: empty point set");
  if (!grad.empty() && grad.size() != n)
    throw std::invalid_argument("l2asd objective: gradient size differs from the point count");
  const double N = double(n);
  auto G = [](double t) { return (1 + 2 * t - 2 * t * t) / 4; };
  auto dG = [](double t) { return (1 - 2 * t) / 2; };
  std::vector<double> rowTerm(n);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
    const double xi = p[i].x, yi = p[i].y;
    double pair = 0, gx = 0, gy = 0;
    for (std::size_t j = 0; j < n; ++j) {
      const double dx = xi - p[j].x, dy = yi - p[j].y;
      const double hx = 1 - std::abs(dx), hy = 1 - std::abs(dy);
      pair += hx * hy;
      // d|t|/dt = sign(t); zero for the point itself.
      gx -= (dx > 0 ? 1.0 : dx < 0 ? -1.0 : 0.0) * hy;
      gy -= (dy > 0 ? 1.0 : dy < 0 ? -1.0 : 0.0) * hx;
    }
    rowTerm[i] = -2 * G(xi) * G(yi) / N + pair / (4 * N * N);
    if (!grad.empty())
      grad[i] = {-2 * dG(xi) * G(yi) / N + gx / (2 * N * N),
                 -2 * G(xi) * dG(yi) / N + gy / (2 * N * N)};
  });
  return 1.0 / 9.0 + std::accumulate(rowTerm.begin(), rowTerm.end(), 0.0);
}

}  // namespace nuld
