#pragma once
// A backend that reads its points from a point-set file with K instances of
// N = spp points (what `nuld optimize` writes): the `optimized:FILE` backend.
//
//  - Points for a non-uniform target (metadata `target: envmap:...`) are
//    already distributed by it. They serve the first bounce's light pair when
//    the scene's environment map is that target; one instance is picked per
//    pixel, as the paper does with its bank of optimized sets.
//  - Points for the uniform target are primary-sample-space points; each
//    (pixel, pair) of the first bounce gets one instance under its own
//    Cranley-Patterson shift, which keeps the estimator unbiased.
// Every other pair (deeper bounces) falls back to Owen-scrambled Sobol
// (DESIGN.md §4: deeper bounces use the classic backends).

#include <memory>
#include <string>

#include "renderer/sampler_backend.h"
#include "sampler/point.h"

namespace nuld {

class PointSetBackend final : public SamplerBackend {
 public:
  PointSetBackend(std::string name, PointSet set, std::string source, std::uint64_t seed);
  static std::unique_ptr<PointSetBackend> load(const std::string &name, const std::string &path,
                                               std::uint64_t seed);

  std::string name() const override { return name_; }
  void prepare(std::size_t spp, const Target *lightTarget) override;
  void primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const override;
  bool distributed(const Target &target, std::uint64_t pixel, std::uint32_t pair,
                   std::span<Point2> out) const override;

  const std::string &targetSpec() const { return targetSpec_; }

 private:
  std::size_t pickInstance(std::uint64_t pixel, std::uint32_t pair) const;

  std::string name_, source_, targetSpec_;
  PointSet set_;
  bool uniform_;
  std::uint64_t seed_;
  std::unique_ptr<SamplerBackend> fallback_;
  const Target *servedTarget_ = nullptr;  // set by prepare()
};

// Whether two target specs name the same target: equal strings, or for
// image:/envmap: the same file reached through different paths.
bool sameTarget(const std::string &specA, const std::string &specB);

}  // namespace nuld
