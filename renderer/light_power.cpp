#include "renderer/light_power.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nuld {

LightPowerChooser::LightPowerChooser(std::span<const double> powers) {
  if (powers.empty()) throw std::invalid_argument("LightPowerChooser: no lights");
  double total = 0;
  for (const double p : powers) {
    if (!(p >= 0) || !std::isfinite(p))
      throw std::invalid_argument("LightPowerChooser: a power is negative or not finite");
    total += p;
  }
  const bool alike = !(total > 0);
  probability_.resize(powers.size());
  cdf_.resize(powers.size());
  double running = 0;
  for (std::size_t i = 0; i < powers.size(); ++i) {
    probability_[i] = alike ? 1.0 / double(powers.size()) : powers[i] / total;
    running += probability_[i];
    cdf_[i] = running;
  }
  cdf_.back() = 1;  // no u in [0, 1) falls past the last light
}

LightPowerChooser::Choice LightPowerChooser::choose(double u) const {
  // The first light whose CDF exceeds u; a light of power 0 has an empty
  // interval and is never chosen.
  std::size_t i = std::size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
  i = std::min(i, cdf_.size() - 1);
  while (probability_[i] == 0 && i > 0) --i;  // u = 1 - ulp against trailing zeros
  return {i, probability_[i]};
}

}  // namespace nuld
