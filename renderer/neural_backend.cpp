#include "renderer/neural_backend.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "renderer/padding.h"
#include "renderer/pointset_backend.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/scrambling.h"

namespace nuld {

NeuralBackend::NeuralBackend(std::string name, const std::string &modelPath, std::uint64_t seed)
    : name_(std::move(name)),
      source_(modelPath),
      generator_(NeuralGenerator::load(modelPath)),
      seed_(seed),
      fallback_(makeClassicBackend("sobol", seed)) {
  if (generator_.gammaDimension() > 0)
    throw std::invalid_argument(
        source_ + ": a model for the family '" + generator_.family().spec() +
        "' needs the shading point's gamma, which the renderer's backends do not receive; "
        "the renderer takes models of one target (the scene's environment map, or uniform)");
  if (const std::string why = generator_.notRandomizedReason(); !why.empty())
    throw std::invalid_argument(source_ + ": " + why +
                                "; a render from them would be biased; retrain without it");
  targetSpec_ = generator_.family().target({})->spec();
  uniform_ = targetSpec_ == "uniform";
}

void NeuralBackend::prepare(std::size_t spp, const Target *lightTarget) {
  const std::size_t n = generator_.settings().n;
  if (spp != n)
    throw std::invalid_argument(source_ + ": the model makes sets of " + std::to_string(n) +
                                " points, but the render asks for " + std::to_string(spp) +
                                " samples per pixel (use --spp " + std::to_string(n) + ")");
  servedTarget_ = nullptr;
  if (!uniform_) {
    if (!lightTarget || !sameTarget(targetSpec_, lightTarget->spec()))
      throw std::invalid_argument(
          source_ + ": the model was trained for '" + targetSpec_ + "', but the scene's " +
          (lightTarget ? "environment map samples '" + lightTarget->spec() + "'"
                       : std::string("has no environment map")));
    servedTarget_ = lightTarget;
  }
  if (bank_.n == n) return;
  const auto start = std::chrono::steady_clock::now();
  const std::size_t sets = std::clamp<std::size_t>((std::size_t(1) << 22) / n, 1, kMaxBankSets);
  bank_ = generator_.generateSets(sets, seed_, {});
  generationSeconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::span<const Point2> NeuralBackend::pick(std::uint64_t pixel, std::uint32_t pair) const {
  return bank_.instance(hash3(seed_ ^ 0x6e657572616cull, pixel, pair) % bank_.instances());
}

void NeuralBackend::primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const {
  if (!uniform_ || pair > SamplePairs::bsdf(0) || out.size() != bank_.n) {
    fallback_->primary(pixel, pair, out);
    return;
  }
  // A Cranley-Patterson shift per (pixel, pair) keeps the estimator unbiased,
  // as for uniform optimized sets.
  const auto points = pick(pixel, pair);
  const std::uint64_t shift = hash3(seed_, pixel, pair);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = {cranleyPatterson(points[i].x, shift), cranleyPatterson(points[i].y, ~shift)};
  shufflePoints(out, shift);
}

bool NeuralBackend::distributed(const Target &target, std::uint64_t pixel, std::uint32_t pair,
                                std::span<Point2> out) const {
  if (&target != servedTarget_ || pair != SamplePairs::light(0) || out.size() != bank_.n)
    return false;
  const auto points = pick(pixel, pair);
  std::copy(points.begin(), points.end(), out.begin());
  shufflePoints(out, hash3(seed_, pixel, pair));
  return true;
}

}  // namespace nuld
