#include "renderer/pointset_backend.h"

#include <filesystem>
#include <stdexcept>

#include "renderer/neural_backend.h"
#include "renderer/padding.h"
#include "sampler/io/pointset_io.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/scrambling.h"

namespace nuld {

bool sameTarget(const std::string &a, const std::string &b) {
  if (a == b) return true;
  const auto colonA = a.find(':'), colonB = b.find(':');
  if (colonA == std::string::npos || colonB == std::string::npos) return false;
  const std::string familyA = a.substr(0, colonA), familyB = b.substr(0, colonB);
  if (familyA != familyB || (familyA != "envmap" && familyA != "image")) return false;
  std::error_code ec;
  const std::filesystem::path pa = a.substr(colonA + 1), pb = b.substr(colonB + 1);
  return std::filesystem::equivalent(pa, pb, ec) && !ec;
}

PointSetBackend::PointSetBackend(std::string name, PointSet set, std::string source,
                                 std::uint64_t seed)
    : name_(std::move(name)),
      source_(std::move(source)),
      set_(std::move(set)),
      seed_(seed),
      fallback_(makeClassicBackend("sobol", seed)) {
  if (set_.n == 0 || set_.instances() == 0)
    throw std::invalid_argument(source_ + ": the point-set file holds no points");
  const auto it = set_.metadata.find("target");
  targetSpec_ = it == set_.metadata.end() ? "uniform" : it->second;
  uniform_ = targetSpec_ == "uniform";
  for (const Point2 &p : set_.points)
    if (!isFinite(p) || p.x < 0 || p.x > 1 || p.y < 0 || p.y > 1)
      throw std::invalid_argument(source_ + ": a point lies outside the unit square");
}

std::unique_ptr<PointSetBackend> PointSetBackend::load(const std::string &name,
                                                       const std::string &path,
                                                       std::uint64_t seed) {
  return std::make_unique<PointSetBackend>(name, readPointSet(path), path, seed);
}

void PointSetBackend::prepare(std::size_t spp, const Target *lightTarget) {
  if (spp != set_.n)
    throw std::invalid_argument(source_ + ": the file holds sets of " + std::to_string(set_.n) +
                                " points, but the render asks for " + std::to_string(spp) +
                                " samples per pixel (use --spp " + std::to_string(set_.n) + ")");
  servedTarget_ = nullptr;
  if (uniform_) return;
  if (!lightTarget || !sameTarget(targetSpec_, lightTarget->spec()))
    throw std::invalid_argument(
        source_ + ": its points follow the target '" + targetSpec_ + "', but the scene's " +
        (lightTarget ? "environment map samples '" + lightTarget->spec() + "'"
                     : std::string("has no environment map")) +
        " (optimize for the scene's map, or use uniform points)");
  servedTarget_ = lightTarget;
}

std::size_t PointSetBackend::pickInstance(std::uint64_t pixel, std::uint32_t pair) const {
  return hash3(seed_ ^ 0x6f7074696d697a65ull, pixel, pair) % set_.instances();
}

void PointSetBackend::primary(std::uint64_t pixel, std::uint32_t pair,
                              std::span<Point2> out) const {
  if (!uniform_ || pair > SamplePairs::bsdf(0) || out.size() != set_.n) {
    fallback_->primary(pixel, pair, out);
    return;
  }
  const auto points = set_.instance(pickInstance(pixel, pair));
  const std::uint64_t shift = hash3(seed_, pixel, pair);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = {cranleyPatterson(points[i].x, shift), cranleyPatterson(points[i].y, ~shift)};
  shufflePoints(out, shift);
}

bool PointSetBackend::distributed(const Target &target, std::uint64_t pixel, std::uint32_t pair,
                                  std::span<Point2> out) const {
  // The target was matched by path once in prepare(); here it is an address.
  if (&target != servedTarget_ || pair != SamplePairs::light(0) || out.size() != set_.n)
    return false;
  const auto points = set_.instance(pickInstance(pixel, pair));
  std::copy(points.begin(), points.end(), out.begin());
  shufflePoints(out, hash3(seed_, pixel, pair));
  return true;
}

std::unique_ptr<SamplerBackend> makeBackend(const std::string &spec, std::uint64_t seed) {
  if (auto classic = makeClassicBackend(spec, seed)) return classic;
  for (const std::string prefix : {"optimized:", "points:"})
    if (spec.rfind(prefix, 0) == 0 && spec.size() > prefix.size())
      return PointSetBackend::load(spec, spec.substr(prefix.size()), seed);
  constexpr std::string_view kNeural = "neural:";
  if (spec.rfind(kNeural, 0) == 0 && spec.size() > kNeural.size())
    return std::make_unique<NeuralBackend>(spec, spec.substr(kNeural.size()), seed);
  throw std::invalid_argument("unknown backend '" + spec +
                              "': expected independent, sobol, halton, optimized:FILE, "
                              "points:FILE or neural:MODEL");
}

}  // namespace nuld
