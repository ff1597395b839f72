#pragma once
// The `neural:MODEL` backend: point sets from a trained neural generator
// (sampler/neural). The generator is conditioned on an offset z; prepare()
// draws a bank of offsets and generates their sets in one batched inference,
// and each (pixel, pair) picks one by hash, so neighbouring pixels get
// different sets as with a per-pixel z, without one network call per pixel.
//
//  - A model for the scene's environment map serves the first bounce's light
//    pair with points already distributed by it (as optimized:FILE does).
//  - A model for the uniform target serves the first bounce's pairs as
//    primary-sample-space points, under a Cranley-Patterson shift per
//    (pixel, pair) that keeps the estimator unbiased.
//  - Models with a distribution parameter gamma (Disney lobes, Gaussian, ...)
//    need the shading point's gamma, which this interface does not pass;
//    prepare() refuses them with that reason. Deeper bounces use Sobol.

#include <memory>
#include <string>

#include "renderer/sampler_backend.h"
#include "sampler/neural/neural_generator.h"

namespace nuld {

class NeuralBackend final : public SamplerBackend {
 public:
  // The bank holds at most this many sets (fewer when N is large: at most
  // 2^22 points in all).
  static constexpr std::size_t kMaxBankSets = 4096;

  NeuralBackend(std::string name, const std::string &modelPath, std::uint64_t seed);

  std::string name() const override { return name_; }
  void prepare(std::size_t spp, const Target *lightTarget) override;
  void primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const override;
  bool distributed(const Target &target, std::uint64_t pixel, std::uint32_t pair,
                   std::span<Point2> out) const override;

  std::size_t bankSets() const { return bank_.instances(); }
  // Seconds prepare() spent generating the bank (the backend's own cost).
  double generationSeconds() const { return generationSeconds_; }

 private:
  std::span<const Point2> pick(std::uint64_t pixel, std::uint32_t pair) const;

  std::string name_, source_, targetSpec_;
  NeuralGenerator generator_;
  std::uint64_t seed_;
  bool uniform_;
  PointSet bank_;
  std::unique_ptr<SamplerBackend> fallback_;
  const Target *servedTarget_ = nullptr;
  double generationSeconds_ = 0;
};

}  // namespace nuld
