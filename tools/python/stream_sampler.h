#pragma once
// nuld.render(..., sampler=ENGINE): a scipy.stats.qmc engine of d = 2, or a
// callable n -> (n, 2) array, or a callable (n, domain=...) -> (n, dims)
// that is told each domain's role (renderer/sample_layout.h), as the
// sampler of a render (tools/python/README.md, "Your own sampler"). The
// one stream is dealt to the image in batches of tiles
// (SamplerBackend::tilesPerStage): per batch and domain one draw of (the
// batch's pixels x spp) samples, pixel k of the batch taking samples
// k spp .. (k + 1) spp - 1, each pixel's set then dealt in a random order
// of its own per domain, as nuld's set samplers are (renderer/padding.h),
// so that domains are matched at random. A sampler not told the role gives
// a 1D domain its points' first coordinates. For a (0, 2) sequence and spp
// a power of two each pixel's set is a net of the stream; the stream's one
// randomization is shared by every pixel. The domains past the ones it
// serves are sobol's.

#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

#include "backends/sobol_rest.h"
#include "renderer/sampler_backend.h"

namespace nuld::python {

namespace py = pybind11;

class StreamSampler final : public SamplerBackend {
 public:
  // `sampler`: the engine or the callable, checked here (render: sampler:
  // ...); `domains`: the first domains it serves, 0 every one. Needs the GIL.
  StreamSampler(py::handle sampler, std::uint32_t domains, std::uint64_t seed);
  ~StreamSampler() override;

  std::string name() const override { return name_; }
  void prepare(std::size_t spp, const SamplingTargets &targets) override;
  std::size_t tilesPerStage() const override { return tilesPerStage_; }
  // Draws the batch's samples, with the GIL; a draw that is not (n, 2), or
  // (n, dims) when told the domain, real numbers in [0, 1) is refused
  // naming the call and the row.
  void stage(std::span<const std::uint64_t> pixels) override;
  void primary(std::uint64_t pixel, std::uint32_t domain, std::span<Point2> out) const override;
  void primary1D(std::uint64_t pixel, std::uint32_t domain, std::span<double> out) const override;
  Report report() const override { return rest_.report(); }

 private:
  py::object draw_;  // ENGINE.random or the callable
  std::string name_, call_;
  bool toldDomain_ = false;  // a callable with a `domain` parameter
  std::string integrator_;
  std::uint32_t domains_;
  std::uint64_t seedKey_;
  SobolRest rest_;  // the domains the sampler leaves
  std::size_t spp_ = 0, tilesPerStage_ = 1;
  std::uint32_t served_ = 0;                 // domains 0 .. served_ - 1 are the sampler's
  std::vector<std::uint32_t> slot_;          // each pixel's place in the staged batch
  std::vector<std::vector<double>> staged_;  // per served domain, the batch's numbers
  // The sample order of (pixel, domain)'s set.
  std::uint64_t shuffleSeed(std::uint64_t pixel, std::uint32_t domain) const;
};

}  // namespace nuld::python
