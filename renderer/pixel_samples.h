#pragma once
// The samples of one pixel: for each dimension pair, the backend's N points,
// fetched the first time a pair is used (paths that end early never pay for
// the pairs of deeper bounces), and for each (pair, sampling context) the
// distributed points, fetched the first time a sample asks for that context.
// Sample i uses point i of whichever set its own context selects, so the
// samples of a pixel whose first hits share a context (the usual case) use
// one set, and a sample with another context still gets a point of a
// properly randomized set. A tile's task holds one per pixel it renders at
// once (up to 16 at low spp), each reused across pixels.

#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

#include "renderer/lobe_tables.h"
#include "renderer/sampler_backend.h"
#include "sampler/targets/grid_target.h"
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
  // such points (asked once per pixel, pair and target). The pointer is
  // valid until the next call.
  const Point2 *distributed(const Target &target, std::uint32_t pair, std::size_t i) {
    const Context &c = context(target, pair);
    if (c.mapped) {  // the one point used, as distributed() would give it
      mapped_ = target.invert(primary(pair, i)).x;
      return &mapped_;
    }
    return c.served ? &c.points[i] : nullptr;
  }

  // Point i of the pair for the route through `table` into `out`, if the
  // backend has such points (else false): the backend's point, which
  // follows the table, or for a backend that maps primary points
  // (mapsPrimaryThrough) the pair's primary point itself, which the route
  // maps by the table's inverse CDF. (An out parameter, written field by
  // field: a point built on the stack and copied whole was read back before
  // its parts' stores could forward, a stall on every first-bounce sample.)
  bool tablePoint(const GridTarget &table, std::uint32_t pair, std::size_t i, RoutePoint &out) {
    const Context &c = context(table, pair);
    if (!c.mapped && !c.served) return false;
    out.value = c.mapped ? primary(pair, i) : c.points[i];
    out.followsTable = !c.mapped;
    return true;
  }

 private:
  struct Context {
    const Target *target = nullptr;
    std::vector<Point2> points;
    bool served = false;
    bool mapped = false;  // served point by point from primary() (mapsPrimaryThrough)
  };
  struct Pair {
    std::vector<Point2> primary;
    bool primaryReady = false;
    std::vector<Context> contexts;  // the first activeContexts are this pixel's
    std::size_t activeContexts = 0;
  };
  // The pair's context for `target`, asked of the backend the first time.
  const Context &context(const Target &target, std::uint32_t pair) {
    Pair &p = slot(pair);
    const auto active = p.contexts.begin() + std::ptrdiff_t(p.activeContexts);
    auto it = std::find_if(p.contexts.begin(), active,
                           [&](const Context &c) { return c.target == &target; });
    if (it != active) return *it;
    if (p.activeContexts == p.contexts.size()) p.contexts.emplace_back();
    Context &c = p.contexts[p.activeContexts++];
    c.target = &target;
    c.mapped = backend_.mapsPrimaryThrough(target);
    if (c.mapped) {
      c.served = true;
    } else {
      c.points.resize(spp_);
      c.served = backend_.distributed(target, pixel_, pair, c.points);
    }
    return c;
  }
  Pair &slot(std::uint32_t pair) {
    if (pair >= pairs_.size()) pairs_.resize(pair + 1);
    return pairs_[pair];
  }

  const SamplerBackend &backend_;
  std::size_t spp_;
  std::uint64_t pixel_ = 0;
  std::vector<Pair> pairs_;
  Point2 mapped_;
};

}  // namespace nuld
