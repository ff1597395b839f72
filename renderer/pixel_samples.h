#pragma once
// The samples of one pixel: for each dimension pair, the backend's N points,
// fetched the first time a pair is used (paths that end early never pay for
// the pairs of deeper bounces). One object per worker, reused across pixels.

#include <cstdint>
#include <vector>

#include "renderer/sampler_backend.h"
#include "sampler/targets/target.h"

namespace nuld {

class PixelSamples {
 public:
  PixelSamples(const SamplerBackend &backend, std::size_t spp) : backend_(backend), spp_(spp) {}

  void startPixel(std::uint64_t pixel) {
    pixel_ = pixel;
    for (Pair &p : pairs_) p.primaryReady = p.distributedKnown = false;
  }

  // Point i of the pair, uniform in [0,1)^2.
  Point2 primary(std::uint32_t pair, std::size_t i) {
    Pair &p = slot(pair);
    if (!p.primaryReady) {
      p.primary.resize(spp_);
      backend_.primary(pixel_, pair, p.primary);
      p.primaryReady = true;
    }
    return p.primary[i];
  }

  // Point i of the pair already distributed by `target`, if the backend has
  // such points (decided once per pixel and pair).
  const Point2 *distributed(const Target &target, std::uint32_t pair, std::size_t i) {
    Pair &p = slot(pair);
    if (!p.distributedKnown) {
      p.distributed.resize(spp_);
      p.hasDistributed = backend_.distributed(target, pixel_, pair, p.distributed);
      p.distributedKnown = true;
    }
    return p.hasDistributed ? &p.distributed[i] : nullptr;
  }

 private:
  struct Pair {
    std::vector<Point2> primary, distributed;
    bool primaryReady = false, distributedKnown = false, hasDistributed = false;
  };
  Pair &slot(std::uint32_t pair) {
    if (pair >= pairs_.size()) pairs_.resize(pair + 1);
    return pairs_[pair];
  }

  const SamplerBackend &backend_;
  std::size_t spp_;
  std::uint64_t pixel_ = 0;
  std::vector<Pair> pairs_;
};

}  // namespace nuld
