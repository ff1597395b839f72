#include "sampler/neural/set_moments.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sampler/loss/box_mass.h"

namespace nuld {

MomentValues momentsAt(Point2 x, Domain domain) {
  MomentValues m;
  double y[3];
  Point2 dy[3];
  int d = 2;
  if (domain == Domain::Square) {
    y[0] = x.x - 0.5, y[1] = x.y - 0.5;
    dy[0] = {1, 0}, dy[1] = {0, 1};
  } else {
    d = 3;
    const double phi = 2 * std::numbers::pi * x.x, cosTheta = 1 - 2 * x.y;
    const double sinTheta = std::max(std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta)), 1e-3);
    y[0] = sinTheta * std::cos(phi), y[1] = sinTheta * std::sin(phi), y[2] = cosTheta;
    const double dSin = 2 * cosTheta / sinTheta;
    dy[0] = {-2 * std::numbers::pi * y[1], dSin * std::cos(phi)};
    dy[1] = {2 * std::numbers::pi * y[0], dSin * std::sin(phi)};
    dy[2] = {0, -2};
  }
  for (int a = 0; a < d; ++a) m.value[m.count] = y[a], m.gradient[m.count++] = dy[a];
  for (int a = 0; a < d; ++a)
    for (int b = a; b < d; ++b)
      m.value[m.count] = y[a] * y[b], m.gradient[m.count++] = y[a] * dy[b] + y[b] * dy[a];
  return m;
}

std::vector<double> targetMoments(const Target &target, Domain domain, int grid) {
  std::vector<Box2> cells;
  cells.reserve(std::size_t(grid) * std::size_t(grid));
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i)
      cells.push_back({{double(i) / grid, double(j) / grid},
                       {double(i + 1) / grid, double(j + 1) / grid}});
  std::vector<double> mass(cells.size());
  exactBoxMasses(target, cells, mass);
  std::vector<double> mean(std::size_t(momentCount(domain)), 0.0);
  double total = 0;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const MomentValues m = momentsAt(0.5 * (cells[c].lo + cells[c].hi), domain);
    for (int a = 0; a < m.count; ++a) mean[std::size_t(a)] += mass[c] * m.value[a];
    total += mass[c];
  }
  for (double &v : mean) v /= total;
  return mean;
}

std::vector<double> momentErrors(std::span<const Point2> points, Domain domain,
                                 const std::vector<double> &targetMeans) {
  std::vector<double> error(targetMeans.size(), 0.0);
  for (const Point2 &p : points) {
    const MomentValues m = momentsAt(p, domain);
    for (std::size_t a = 0; a < error.size(); ++a) error[a] += m.value[a];
  }
  for (std::size_t a = 0; a < error.size(); ++a)
    error[a] = error[a] / double(std::max<std::size_t>(1, points.size())) - targetMeans[a];
  return error;
}

}  // namespace nuld
