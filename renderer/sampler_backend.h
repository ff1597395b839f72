#pragma once
// The swap point between the sampler module and the renderer
// (docs/architecture.md, "Sampler backends").
//
// For every pixel and every *domain* of a path (renderer/sample_layout.h:
// the camera's 2D, then per bounce a 1D light choice, a 2D light sample, a
// 1D lobe choice, a 2D BSDF direction and a 1D roulette number) a backend
// hands out N samples of the domain's dimension, N = spp; sample i of a
// pixel uses sample i of each domain. For a 2D domain a backend gives either
//  - primary-sample-space points, uniform in [0,1)^2, which the light or the
//    BSDF maps by its own inverse CDF; or
//  - for a domain and a *sampling context* it serves, points already
//    distributed by the context's target, which the caller uses with that
//    target's pdf. The context is the target being sampled: the scene's
//    environment map for a light domain, the shading point's tabulated lobe
//    (renderer/lobe_tables.h) for a BSDF domain. Optimized and neural sets
//    serve the contexts they were made for, sobol-tabulated serves every lobe
//    through its inverse CDF; a declined context gets primary points and the
//    classic mapping.
// 1D domains are always primary: uniform numbers in [0, 1).

#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/sample_layout.h"
#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

// Every target a render may ask a backend for: the context of the light
// domains and, when the backend samples lobes, those of the BSDF domains; and the
// image's size, whose pixel (x, y) is asked as pixel y * width + x (a
// backend that orders its samples over the screen, zsobol, needs it).
struct SamplingTargets {
  const Target *light = nullptr;        // the environment map's, null without one
  std::vector<const Target *> lobes{};  // every lobe table (LobeTables::targets)
  std::uint32_t width = 0, height = 0;  // 0: not a render (a backend's own tests)
  // The domains a path of the render may ask: 0 .. domains - 1 (one
  // bounce's under direct, maxDepth's under path; 0: not a render).
  std::uint32_t domains = 0;
  // The integrator as the command line names it ("path", "direct"; "": not
  // a render), for samplers that are told (plugins, Python).
  std::string integrator{};
};

// What prepare() throws when the backend cannot serve a render (sets of
// another N, points that follow none of the scene's targets, a model that
// makes none of them): a statement about this backend and this scene, which
// a study records as a skipped row. Any other exception is a failure.
class BackendRefusal : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

class SamplerBackend {
 public:
  virtual ~SamplerBackend() = default;

  // The name as given on the command line (e.g. "sobol", "optimized:PATHS").
  virtual std::string name() const = 0;

  // Whether BSDF domains should be asked with lobe contexts: the renderer then
  // tabulates the lobes of the scene's materials (only then: classic
  // backends never pay for the tables).
  virtual bool samplesLobes() const { return false; }

  // Checks that the backend can serve `spp` samples per pixel for a scene
  // with these targets, and remembers which ones it serves (by address: the
  // same objects are passed to distributed()); throws BackendRefusal saying
  // why not (a point-set file of another N, or points that follow no target
  // of the scene).
  virtual void prepare(std::size_t spp, const SamplingTargets &targets) {}

  // A backend that deals one stateful stream (Python's sampler=ENGINE)
  // cannot be asked in any order. It gives the tiles it stages at once, and
  // the renderer then renders the image in batches of that many tiles, one
  // batch after another, calling stage() on its own thread with the pixels
  // of each batch (tile by tile, rows within a tile) before rendering it;
  // primary() then serves those pixels. 0, every other backend: tiles render
  // in any order.
  virtual std::size_t tilesPerStage() const { return 0; }
  virtual void stage(std::span<const std::uint64_t> pixels) {}

  // N = out.size() uniform points in [0,1)^2 for (pixel, domain), a 2D
  // domain. A pure function of its arguments (and of the staged batch), so
  // renders are deterministic for any thread count.
  virtual void primary(std::uint64_t pixel, std::uint32_t domain, std::span<Point2> out) const = 0;
  // N = out.size() uniform numbers in [0,1) for (pixel, domain), a 1D
  // domain: each backend's own 1D construction. Pure, as primary().
  virtual void primary1D(std::uint64_t pixel, std::uint32_t domain,
                         std::span<double> out) const = 0;

  // Fills `out` with points distributed by `target` (in its unit-square
  // parameterization) and returns true, or returns false when this backend
  // has no such points for the domain: the caller then maps primary() points
  // classically (the light through target.invert(), a BSDF by its own
  // sample()). Also a pure function of its arguments.
  virtual bool distributed(const Target &target, std::uint64_t pixel, std::uint32_t domain,
                           std::span<Point2> out) const {
    return false;
  }

  // Whether distributed(target, ...) is exactly primary() mapped point by
  // point through target.invert() (sobol-tabulated's lobes). The renderer
  // then maps only the points it uses, from the domain's primary points it
  // already holds, instead of asking for a whole set per context.
  virtual bool mapsPrimaryThrough(const Target &target) const { return false; }

  // What a backend has to say of its sampling since prepare(), for the user
  // and the studies (sampling never reads it): one statistics object, so
  // that the interface's sampling calls stay apart from its diagnostics.
  struct PairUse {
    std::string pair;
    std::uint64_t served = 0, fellBack = 0;
  };
  struct Report {
    // Per kind of domain ("light", "bsdf", "primary"), the first-bounce
    // contexts (pixel, domain) a learned backend's sets served and those that
    // fell back to its classic sampler; empty for backends without sets.
    std::vector<PairUse> pairUse;
    // What the last prepare() decided that a user should hear ("" for
    // nothing): e.g. the lobe tables a learned backend left to its
    // fallback, or the domains a plugin leaves to sobol.
    std::string note;
    // The seconds the last prepare() spent making sets it found nowhere (a
    // neural model's banks): one-time setup, which a study reports apart
    // from render time. 0 for backends whose sets are made before a render.
    double setsMadeSeconds = 0;
  };
  virtual Report report() const { return {}; }
};

}  // namespace nuld
