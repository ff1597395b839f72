#pragma once
// A user's sampler (plugin:PATH, Python's sampler=ENGINE) serves the first
// pairs of a render, or all of them; the rest take Owen-Sobol, and the
// backend's report says so. One piece for both, so that they split the pairs
// and say it alike.

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "backends/backend_registry.h"

namespace nuld {

class SobolRest {
 public:
  explicit SobolRest(std::uint64_t seed) : sobol_(makeClassicBackend(BackendKind::Sobol, seed)) {}

  // The render's first `served` pairs (at most targets.pairs) are `who`'s
  // ("the plugin"), the rest sobol's, prepared for the render.
  void prepare(const std::string &who, std::uint32_t served, std::size_t spp,
               const SamplingTargets &targets) {
    served_ = std::min(served, targets.pairs);
    sobol_->prepare(spp, targets);
    note_ = served_ == 0 ? who + " serves no pair; every point is sobol's"
            : served_ < targets.pairs
                ? who + " serves the first " + std::to_string(served_) + " of the " +
                      std::to_string(targets.pairs) + " pairs; the rest are sobol's"
                : "";
  }
  std::uint32_t served() const { return served_; }
  // Sobol's points for a pair the sampler leaves.
  void primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const {
    sobol_->primary(pixel, pair, out);
  }
  // The report of a backend whose only news is the split.
  SamplerBackend::Report report() const {
    SamplerBackend::Report r;
    r.note = note_;
    return r;
  }

 private:
  std::unique_ptr<SamplerBackend> sobol_;
  std::uint32_t served_ = 0;
  std::string note_;
};

}  // namespace nuld
