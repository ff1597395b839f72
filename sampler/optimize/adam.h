#pragma once
// Adam (Kingma & Ba 2014) on a vector of 2D parameters. The moments are part
// of the optimizer state so that checkpoints resume bit-identically.

#include <cmath>
#include <span>

#include "sampler/point.h"

namespace nuld {

struct AdamSettings {
  double beta1 = 0.9, beta2 = 0.999, epsilon = 1e-8;
};

// One step (t = 1, 2, ...) with learning rate lr; updates params, m and v.
inline void adamStep(std::span<Point2> params, std::span<const Point2> grad, std::span<Point2> m,
                     std::span<Point2> v, long t, double lr, const AdamSettings &s = {}) {
  const double c1 = 1 - std::pow(s.beta1, double(t)), c2 = 1 - std::pow(s.beta2, double(t));
  for (std::size_t i = 0; i < params.size(); ++i)
    for (int k = 0; k < 2; ++k) {
      const double g = grad[i][k];
      m[i][k] = s.beta1 * m[i][k] + (1 - s.beta1) * g;
      v[i][k] = s.beta2 * v[i][k] + (1 - s.beta2) * g * g;
      params[i][k] -= lr * (m[i][k] / c1) / (std::sqrt(v[i][k] / c2) + s.epsilon);
    }
}

}  // namespace nuld
