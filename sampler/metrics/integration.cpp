#include "sampler/metrics/integration.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace nuld {

TestIntegrand makeTestIntegrand(const std::string &name) {
  if (name == "step") return {name, [](Point2 p) { return p.x < 0.5 ? 1.0 : 0.0; }, 0.5};
  if (name == "disc")
    return {name, [](Point2 p) { return p.x * p.x + p.y * p.y <= 1 ? 1.0 : 0.0; },
            std::numbers::pi / 4};
  if (name == "bilinear") return {name, [](Point2 p) { return p.x * p.y; }, 0.25};
  if (name == "gaussian") {
    constexpr double s = 0.15, cx = 0.4, cy = 0.6;
    auto axis = [](double c) {
      return s * std::sqrt(std::numbers::pi / 2) *
             (std::erf((1 - c) / (s * std::numbers::sqrt2)) +
              std::erf(c / (s * std::numbers::sqrt2)));
    };
    return {name,
            [](Point2 p) {
              const double dx = p.x - cx, dy = p.y - cy;
              return std::exp(-(dx * dx + dy * dy) / (2 * s * s));
            },
            axis(cx) * axis(cy)};
  }
  throw std::invalid_argument("unknown integrand '" + name +
                              "' (expected step, disc, bilinear or gaussian)");
}

double estimateIntegral(std::span<const Point2> points, const Target &target,
                        const std::function<double(Point2)> &f) {
  if (points.empty()) throw std::invalid_argument("estimateIntegral: empty point set");
  double sum = 0;
  for (const Point2 &p : points) {
    const double q = target.pdf(p);
    if (q > 0) sum += f(p) / q;
  }
  return sum / double(points.size());
}

}  // namespace nuld
