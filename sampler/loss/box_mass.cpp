#include "sampler/loss/box_mass.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <stdexcept>
#include <vector>

#include "sampler/loss/point_grid.h"

namespace nuld {

void exactBoxMasses(const Target &target, std::span<const Box2> boxes, std::span<double> out) {
  if (out.size() != boxes.size()) throw std::invalid_argument("exactBoxMasses: size mismatch");
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, boxes.size(), 512), [&](const auto &r) {
    for (std::size_t m = r.begin(); m < r.end(); ++m) out[m] = target.mass(boxes[m]);
  });
}

void MonteCarloBoxMass::estimate(std::span<const Box2> boxes, std::span<double> out,
                                 Rng &rng) const {
  if (out.size() != boxes.size()) throw std::invalid_argument("MonteCarloBoxMass: size mismatch");
  if (k_ == 0) throw std::invalid_argument("MonteCarloBoxMass: needs at least one space sample");
  std::vector<Point2> samples(k_);
  for (Point2 &s : samples) s = {rng.uniform(), rng.uniform()};
  std::vector<double> weights(k_);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, k_, 4096), [&](const auto &r) {
    for (std::size_t k = r.begin(); k < r.end(); ++k)
      weights[k] = target_.pdf(samples[k]) / double(k_);
  });
  const PointGrid grid(samples, weights);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, boxes.size(), 256), [&](const auto &r) {
    for (std::size_t m = r.begin(); m < r.end(); ++m) out[m] = grid.boxSum(boxes[m].clipped());
  });
}

}  // namespace nuld
