#pragma once
// Chooses one of several lights with a probability proportional to its
// power (pbrt-v4's PowerLightSampler), from a number of its own: the path's
// light-choice dimension. The number left over after the choice, rescaled
// to [0, 1), is not reused: a light's position takes a 2D draw of its own.

#include <cstddef>
#include <span>
#include <vector>

namespace nuld {

class LightPowerChooser {
 public:
  // Each light's power: finite and >= 0 (the scene parser refuses others);
  // when every one is 0 the lights are chosen alike.
  explicit LightPowerChooser(std::span<const double> powers);

  std::size_t size() const { return cdf_.size(); }
  struct Choice {
    std::size_t index;
    double probability;  // > 0
  };
  // The light whose CDF interval holds u (u in [0, 1)).
  Choice choose(double u) const;
  // The probability of choosing light i (for the MIS weight of a BSDF
  // sample that hits it).
  double probability(std::size_t i) const { return probability_[i]; }

 private:
  std::vector<double> cdf_, probability_;  // cdf_[i]: P(index <= i); the last is 1
};

}  // namespace nuld
