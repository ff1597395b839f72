#pragma once
// The samples of one pixel: for each domain of the sample layout, the
// backend's N points or numbers, fetched the first time the domain is used
// (paths that end early never pay for the domains of deeper bounces), and
// for each (2D domain, sampling context) the
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
    for (Domain &p : domains_) {
      p.primaryReady = false;
      p.numbersReady = false;
      p.activeContexts = 0;  // their buffers stay allocated for the next pixel
    }
  }

  // Number i of the 1D domain, uniform in [0,1).
  double number(std::uint32_t domain, std::size_t i) {
    Domain &p = slot(domain);
    if (!p.numbersReady) {
      p.numbers.resize(spp_);
      backend_.primary1D(pixel_, domain, p.numbers);
      p.numbersReady = true;
    }
    return p.numbers[i];
  }

  // Point i of the 2D domain, uniform in [0,1)^2.
  Point2 primary(std::uint32_t domain, std::size_t i) {
    Domain &p = slot(domain);
    if (!p.primaryReady) {
      p.primary.resize(spp_);
      backend_.primary(pixel_, domain, p.primary);
      p.primaryReady = true;
    }
    return p.primary[i];
  }

  // Point i of the domain already distributed by `target`, if the backend has
  // such points (asked once per pixel, domain and target). The pointer is
  // valid until the next call.
  const Point2 *distributed(const Target &target, std::uint32_t domain, std::size_t i) {
    const Context &c = context(target, domain);
    if (c.mapped) {  // the one point used, as distributed() would give it
      mapped_ = target.invert(primary(domain, i)).x;
      return &mapped_;
    }
    return c.served ? &c.points[i] : nullptr;
  }

  // Point i of the domain for the route through `table` into `out`, if the
  // backend has such points (else false): the backend's point, which
  // follows the table, or for a backend that maps primary points
  // (mapsPrimaryThrough) the domain's primary point itself, which the route
  // maps by the table's inverse CDF. (An out parameter, written field by
  // field: a point built on the stack and copied whole was read back before
  // its parts' stores could forward, a stall on every first-bounce sample.)
  bool tablePoint(const GridTarget &table, std::uint32_t domain, std::size_t i, RoutePoint &out) {
    const Context &c = context(table, domain);
    if (!c.mapped && !c.served) return false;
    out.value = c.mapped ? primary(domain, i) : c.points[i];
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
  // One domain's samples (a 2D domain's points and contexts, or a 1D
  // domain's numbers).
  struct Domain {
    std::vector<Point2> primary;
    bool primaryReady = false;
    std::vector<double> numbers;
    bool numbersReady = false;
    std::vector<Context> contexts;  // the first activeContexts are this pixel's
    std::size_t activeContexts = 0;
  };
  // The domain's context for `target`, asked of the backend the first time.
  const Context &context(const Target &target, std::uint32_t domain) {
    Domain &p = slot(domain);
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
      c.served = backend_.distributed(target, pixel_, domain, c.points);
    }
    return c;
  }
  Domain &slot(std::uint32_t domain) {
    if (domain >= domains_.size()) domains_.resize(domain + 1);
    return domains_[domain];
  }

  const SamplerBackend &backend_;
  std::size_t spp_;
  std::uint64_t pixel_ = 0;
  std::vector<Domain> domains_;
  Point2 mapped_;
};

}  // namespace nuld
