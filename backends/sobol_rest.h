#pragma once
// A user's sampler (plugin:PATH, Python's sampler=ENGINE) serves some
// domains of a render (renderer/sample_layout.h), or all of them; the rest
// take Owen-Sobol, and the backend's report says so. One piece for both, so
// that they split the domains and say it alike.

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "backends/backend_registry.h"

namespace nuld {

class SobolRest {
 public:
  explicit SobolRest(std::uint64_t seed) : sobol_(makeClassicBackend(BackendKind::Sobol, seed)) {}

  // served[k]: whether `who` ("the plugin") serves domain k of the render
  // (those past served.size(): sobol's); prepared for the render.
  void prepare(const std::string &who, std::vector<bool> served, std::size_t spp,
               const SamplingTargets &targets) {
    served.resize(targets.domains, false);
    served_ = std::move(served);
    sobol_->prepare(spp, targets);
    const auto count = std::size_t(std::count(served_.begin(), served_.end(), true));
    std::string left;
    for (std::uint32_t d = 0; d < served_.size(); ++d)
      if (!served_[d]) left += (left.empty() ? "" : ", ") + domainName(d);
    note_ = count == 0 ? who + " serves no domain; every sample is sobol's"
            : count < served_.size()
                ? who + " serves " + std::to_string(count) + " of the " +
                      std::to_string(served_.size()) + " domains; sobol serves " + left
                : "";
  }
  bool serves(std::uint32_t domain) const { return domain < served_.size() && served_[domain]; }
  // Sobol's samples for a domain the sampler leaves.
  void primary(std::uint64_t pixel, std::uint32_t domain, std::span<Point2> out) const {
    sobol_->primary(pixel, domain, out);
  }
  void primary1D(std::uint64_t pixel, std::uint32_t domain, std::span<double> out) const {
    sobol_->primary1D(pixel, domain, out);
  }
  // The report of a backend whose only news is the split.
  SamplerBackend::Report report() const {
    SamplerBackend::Report r;
    r.note = note_;
    return r;
  }

  // "domain 4 (bounce 0's bsdf)": a domain as the layout numbers it.
  static std::string domainName(std::uint32_t domain) {
    const SampleDomain d = SampleLayout::domain(domain);
    if (d.role == SampleRole::Camera) return "domain 0 (the camera's)";
    return "domain " + std::to_string(domain) + " (bounce " + std::to_string(d.bounce) + "'s " +
           toString(d.role) + ")";
  }

 private:
  std::unique_ptr<SamplerBackend> sobol_;
  std::vector<bool> served_;
  std::string note_;
};

}  // namespace nuld
