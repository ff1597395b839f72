#pragma once
// A unidirectional path tracer with next-event estimation of the environment
// light and BSDF sampling, combined by multiple importance sampling with the
// power heuristic (Veach 1997), and Russian roulette from the third hit on.
// The direct-lighting mode stops after the first bounce: it isolates the
// estimator that the sampler backends differ in. The light mode estimates
// that direct lighting by environment-map sampling alone (no BSDF sample, no
// MIS weight): the estimator of the supplement's environment-map experiment,
// where only the light's points vary between backends. The BSDF mode is its
// mirror image: the first bounce by BSDF sampling alone (the estimator in
// which only the BSDF sample's numbers vary: its lobe choice and direction).
//
// BSDF sampling at a Disney material samples its tabulated lobe
// (renderer/lobe_tables.h) when the backend hands over points distributed by
// the shading point's table (in a defensive mixture with the material's own
// sampler), and the material's own lobe-selection mapping otherwise (and in
// the bins whose route is the material's); every estimate divides by the
// density of the strategy that drew it, and the MIS weights of both
// strategies take the material's own pdf (BsdfSample::misPdf); misWeight is
// the one place a weight is computed.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "materials/rgb.h"
#include "materials/sampling.h"
#include "renderer/lobe_tables.h"
#include "renderer/pixel_samples.h"
#include "renderer/scene.h"

namespace nuld {

enum class IntegratorKind { Path, Direct, Light, Bsdf };
inline constexpr auto kIntegratorNames =
    enumTable<IntegratorKind>("integrator", {{"path", IntegratorKind::Path},
                                             {"direct", IntegratorKind::Direct},
                                             {"light", IntegratorKind::Light},
                                             {"bsdf", IntegratorKind::Bsdf}});
constexpr const auto &enumNames(IntegratorKind) { return kIntegratorNames; }
inline IntegratorKind parseIntegrator(const std::string &name) {
  return kIntegratorNames.parse(name);
}

// The environment light as `kind` samples it: the scene's, except that the
// light integrator, which adds no BSDF samples, samples a compensated map
// without its compensation (environment_light.h); null without a map.
const EnvironmentLight *sampledLight(const Scene &scene, IntegratorKind kind);

// A traced ray as Embree saw it, for the benchmark that replays the
// renderer's rays through Embree alone.
struct RecordedRay {
  float origin[3], direction[3];
};

struct PathCounters {
  std::uint64_t rays = 0;                        // intersection and shadow rays traced
  std::uint64_t rejected = 0;                    // non-finite sample values dropped (should stay 0)
  std::uint64_t classicFallbacks = 0;            // first-bounce lobe contexts the backend declined
  std::vector<RecordedRay> *recorder = nullptr;  // when set, every ray is appended
};

// wo in the shading frame the integrator uses at `hit` (its shading normal
// turned to wo's side), as the lobe tables are asked with it.
Vec3 shadingLocal(const SurfaceHit &hit, Vec3 wo);

class PathIntegrator {
 public:
  // `lobes`: the tables BSDF domains are asked for (null: never asked).
  // `rouletteDepth`: the first hit (0-based) where Russian roulette may end a
  // path; the default 2 never cuts the first two hits' direct light.
  PathIntegrator(const Scene &scene, IntegratorKind kind, int maxDepth,
                 const LobeTables *lobes = nullptr, int rouletteDepth = 2);

  // The radiance of up to kMaxPaths paths: path k starts on camera ray
  // rays[k], whose closest hit hits[k] the caller traces (the renderer traces
  // camera rays in coherent packets, EmbreeScene::intersectCoherent), and is
  // sample indices[k] of the pixel *samples[k]; out[k] receives it. The
  // paths advance together one bounce at a time, so the random reads of a
  // bounce (the light's tables, the meshes, the map's texels of escaping
  // rays) are issued for all of them before any is waited on. Each path's
  // arithmetic is that of a path traced alone: the result does not depend on
  // which paths share a call.
  static constexpr std::size_t kMaxPaths = 16;
  void radiance(std::span<const Ray> rays, std::span<const std::optional<SurfaceHit>> hits,
                std::span<PixelSamples *const> samples, std::span<const std::size_t> indices,
                std::span<Rgb> out, PathCounters &counters) const;

  // One path between bounces; defined (and used only) in path_integrator.cpp.
  struct PathState;

 private:
  // The phases of one bounce over a packet of paths, in the order radiance()
  // runs them; each skips the paths that have ended.
  // What each path finds at `hit`: the environment when it escaped (ending
  // it), the end of its depth or roulette, else its shading; returns whether
  // any path goes on.
  bool arrive(std::span<PathState> paths, std::span<const std::optional<SurfaceHit>> hits,
              int depth) const;
  // Each path's BSDF strategy: the backend's point through the lobe table when
  // it serves the context, else the material's own sample().
  void chooseBsdfStrategies(std::span<PathState> paths, int depth, PathCounters &counters) const;
  // Next-event estimation of the environment, MIS-weighted against BSDF
  // sampling by the material's own pdf (whichever strategy draws the BSDF
  // sample).
  void addLightSamples(std::span<PathState> paths, int depth, PathCounters &counters) const;
  // Samples each path's continuation and traces it into `hits`; returns
  // whether any path goes on.
  bool continuePaths(std::span<PathState> paths, int depth,
                     std::span<std::optional<SurfaceHit>> hits, PathCounters &counters) const;

  // The estimators an integrator kind runs, chosen once: path and direct
  // both, combined by MIS; light (next-event estimation alone, the first
  // bounce) and bsdf (BSDF sampling alone, the first bounce) one each.
  struct Strategies {
    bool light = true, bsdf = true;
    static Strategies of(IntegratorKind kind);
  };
  // The MIS weight of a sample drawn with density `pdf` by one strategy
  // against `otherPdf`, the other strategy's at the same direction: the
  // power heuristic when both run, 1 when one runs alone.
  double misWeight(double pdf, double otherPdf) const;
  // Adds the radiance Le of light `light` (SceneLights::light's numbering)
  // that path p's ray met, weighed against that light's own sampling when a
  // BSDF sample drew the ray.
  void addEmitted(PathState &p, std::size_t light, Rgb Le) const;
  // Whether a rectangle or sphere light other than shape `except` blocks
  // the shadow ray before its tMax (they are not in the geometry).
  bool shadowedByShapes(const Ray &shadow, std::size_t except) const;

  const Scene &scene_;
  const EnvironmentLight *light_;  // sampledLight()
  const LobeTables *lobes_;
  int maxDepth_, rouletteDepth_;
  Strategies strategies_;
  // The probability that next-event estimation picks the environment (1
  // without emitters), which its MIS weight for an escaping ray takes.
  double environmentChoice_;
};

}  // namespace nuld
