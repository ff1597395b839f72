#pragma once
// The supplement's schedules: the learning rate decays log-linearly from
// start to end over all epochs; the sigmoid scale alpha rises linearly from
// start to end over the first `rampFraction` of the epochs, then stays.

#include <algorithm>
#include <cmath>

namespace nuld {

inline double logLinear(double start, double end, int epoch, int epochs) {
  if (epochs <= 1) return start;
  const double t = double(epoch) / double(epochs - 1);
  return start * std::pow(end / start, t);
}

inline double linearRamp(double start, double end, double rampFraction, int epoch, int epochs) {
  const double rampEpochs = rampFraction * epochs;
  if (rampEpochs <= 1) return end;
  const double t = std::min(1.0, double(epoch) / (rampEpochs - 1));
  return start + (end - start) * t;
}

}  // namespace nuld
