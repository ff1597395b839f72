#pragma once
// The blue-noise baselines as point-set generators: K sets of N points from
// independent uniform starts, each either optimized for the target directly
// (sliced optimal transport or adaptive Gaussian blue noise) or optimized
// for the uniform square and then mapped by the target's inverse CDF ("uniform
// then mapped", as the supplement compares them). `nuld generate` and
// `nuld study integrate` both make their sets here.

#include <cstdint>
#include <functional>
#include <string>

#include "sampler/bluenoise/gaussian_blue_noise.h"
#include "sampler/bluenoise/sliced_ot.h"
#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

enum class BlueNoiseMethod { SlicedOt, Gaussian };

// A method and whether its sets are mapped, as one name ("sot-mapped").
struct BlueNoiseKind {
  BlueNoiseMethod method;
  bool mapped;
  friend bool operator==(BlueNoiseKind, BlueNoiseKind) = default;
};
inline constexpr auto kBlueNoiseNames = enumTable<BlueNoiseKind>(
    "blue-noise method", {{"sot", {BlueNoiseMethod::SlicedOt, false}},
                          {"sot-mapped", {BlueNoiseMethod::SlicedOt, true}},
                          {"gbn", {BlueNoiseMethod::Gaussian, false}},
                          {"gbn-mapped", {BlueNoiseMethod::Gaussian, true}}});

struct BlueNoiseRequest {
  BlueNoiseMethod method = BlueNoiseMethod::SlicedOt;
  bool mapped = false;  // optimize for the uniform square, then map
  SlicedOtSettings sot;
  GaussianBlueNoiseSettings gbn;
  std::uint64_t seed = 0;  // starts, directions and target samples

  // "sot", "sot-mapped", "gbn" or "gbn-mapped".
  std::string name() const;
};

// Parses the names of kBlueNoiseNames; throws std::invalid_argument otherwise.
BlueNoiseRequest parseBlueNoiseName(const std::string &name);

// The sets, with metadata (generator, settings, target). `progress(done,
// total)` counts iterations over all sets.
PointSet blueNoiseSets(const BlueNoiseRequest &request, const Target &target, std::size_t n,
                       std::size_t instances, const std::function<void(long, long)> &progress = {});

}  // namespace nuld
