#include <cmath>
#include <sstream>
#include <stdexcept>

#include "sampler/io/round_trip.h"
#include "sampler/neural/neural_trainer.h"

// The trainer's settings, which need no LibTorch (the trainer itself is in
// the plugin: neural_trainer.cpp).

namespace nuld {

std::string TrainerSettings::describe() const {
  const auto r = [](double v) { return formatRoundTrip(v); };
  std::ostringstream s;
  s << "steps=" << steps << " batch=" << batch << " boxes=" << boxes
    << " box_kind=" << toString(boxKind) << " lr=" << r(lrStart) << " lr_end=" << r(lrEnd)
    << " alpha=" << r(alphaStart) << " alpha_end=" << r(alphaEnd) << " ramp=" << r(rampFraction)
    << " cutoff=" << r(cutoff) << " pullback=" << toString(pullback) << " seed=" << seed
    << " validation=" << validationSets << " validation_grid=" << validationGrid;
  if (shiftedSets) s << " shifted=1";  // only when on: older checkpoints keep their line
  return s.str();
}

void TrainerSettings::validate() const {
  auto bad = [](const std::string &what) { throw std::invalid_argument("train: " + what); };
  if (steps < 1) bad("steps must be positive");
  if (batch < 1) bad("batch must be positive");
  if (boxes < 1) bad("boxes must be positive");
  const auto positive = [](double v) { return v > 0 && std::isfinite(v); };
  if (!(positive(lrStart) && positive(lrEnd))) bad("learning rates must be finite and positive");
  if (!(positive(alphaStart) && positive(alphaEnd))) bad("alpha must be finite and positive");
  // Beyond this the sigmoid is a hard box edge: no gradient reaches a point.
  if (alphaStart > 1e7 || alphaEnd > 1e7) bad("alpha must be at most 1e7");
  if (!(rampFraction >= 0 && rampFraction <= 1)) bad("ramp must be in [0, 1]");
  if (validationGrid < 8) bad("validation grid must be at least 8");
}

}  // namespace nuld
