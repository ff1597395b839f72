#pragma once
// The samples of one pixel: for each dimension pair, the backend's N points,
// fetched the first time a pair is used (paths that end early never pay for
// the pairs of deeper bounces), and for each (pair, sampling context) the
// distributed points, fetched the first time a sample asks for that context.
// Sample i uses point i of whichever set its own context selects, so the
// samples of a pixel whose first hits share a context (the usual case) use
// one set, and a sample with another context still gets a point of a
// properly randomized set. One object per worker, reused across pixels.

#include <algorithm>
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
    for (Pair &p : pairs_) {
      p.primaryReady = false;
      p.activeContexts = 0;  // their buffers stay allocated for the next pixel
    }
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
  // such points (asked once per pixel, pair and target).
  const Point2 *distributed(const Target &target, std::uint32_t pair, std::size_t i) {
    Pair &p = slot(pair);
    const auto active = p.contexts.begin() + std::ptrdiff_t(p.activeContexts);
    auto it = std::find_if(p.contexts.begin(), active,
                           [&](const Context &c) { return c.target == &target; });
    if (it == active) {
      if (p.activeContexts == p.contexts.size()) p.contexts.emplace_back();
      it = p.contexts.begin() + std::ptrdiff_t(p.activeContexts++);
      it->target = &target;
      it->points.resize(spp_);
      it->served = backend_.distributed(target, pixel_, pair, it->points);
    }
    return it->served ? &it->points[i] : nullptr;
  }

 private:
  struct Context {
    const Target *target = nullptr;
    std::vector<Point2> points;
    bool served = false;
  };
  struct Pair {
    std::vector<Point2> primary;
    bool primaryReady = false;
    std::vector<Context> contexts;  // the first activeContexts are this pixel's
    std::size_t activeContexts = 0;
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
