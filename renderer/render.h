#pragma once
// The render loop: TBB over 16x16 tiles, each pixel integrated in one task in
// sample order, so an image is a pure function of (scene, settings, backend)
// for any thread count.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "renderer/path_integrator.h"
#include "renderer/sampler_backend.h"
#include "renderer/scene.h"
#include "sampler/io/image_io.h"

namespace nuld {

// The estimator's revision, raised whenever a change alters what renders
// converge to or how noisy they are (2: the terminator policy and roulette
// from the third hit; 3: the sample layout's domains, the lobe choice a
// number of its own). Study references record it, so one made by another
// revision is refused rather than compared against.
inline constexpr int kRendererRevision = 3;

// The longest path a scene, a command or the Python module may ask for.
inline constexpr int kMaxDepthLimit = 1000;

struct RenderSettings {
  int width = 256, height = 256;
  std::size_t spp = 16;
  IntegratorKind integrator = IntegratorKind::Path;
  int maxDepth = 5;
  int rouletteDepth = 2;  // the first hit (0-based) where Russian roulette may end a path
  // The lobe tables of a backend that samples lobes (built from the scene's
  // materials on the first such render and kept in Scene::lobeTables); see
  // lobeTablesFor.
  LobeTableSettings lobeTables{};
};

// How a front end names the settings it overrides, for the messages of
// RenderOverrides::check: the command line's options, or the Python module's
// keyword arguments.
struct OverrideNames {
  std::string prefix, spp, resolution, resolutionScale, integrator, maxDepth, lobeMix,
      lobeDefensive, lobeBounces;
  // --spp, --res, --res-scale, --integrator, --max-depth, --lobe-*
  static OverrideNames options();
  // render: spp, resolution, resolution_scale, integrator, max_depth, lobe_*
  static OverrideNames python();
};

// The memory a render with `s` takes beyond its scene: the image (3 floats a
// pixel), the copy of it its caller keeps while writing or returning it (the
// tone-mapped preview nuld render writes beside the EXR, the array
// nuld.render returns: 3 floats a pixel), and each thread's sample buffers
// (spp points of every dimension pair a path may reach, and of a context
// each; renderer/pixel_samples.h).
double renderMemoryBytes(const RenderSettings &s);

// What a command changes of a scene's render settings (`nuld render`, the
// render study, the Python module): an unset field keeps the scene's value.
// The values are checked here, once, and named in the caller's terms.
struct RenderOverrides {
  std::optional<std::size_t> spp;
  std::optional<int> width, height;  // height unset: the scene's aspect at that width
  double resolutionScale = 1;        // of the scene's resolution, when width is unset
  std::optional<IntegratorKind> integrator;
  std::optional<int> maxDepth;
  std::optional<double> lobeMix;  // LobeTableSettings::samplingMix
  std::optional<LobeRouting> lobeRouting;
  std::optional<double> lobeDefensive;  // LobeTableSettings::defensive
  std::optional<int> lobeBounces;       // LobeTableSettings::bounces

  // Throws std::invalid_argument "NAME: expected ... (got V)" for the first
  // value out of range.
  void check(const OverrideNames &names) const;
  // The settings with the overrides applied, after check(names); throws
  // std::invalid_argument "RES: a W x H render at S spp needs about X of
  // memory, more than this machine's Y" (requireMemory, renderMemoryBytes)
  // for settings the machine cannot render, before anything is allocated.
  RenderSettings appliedTo(RenderSettings s,
                           const OverrideNames &names = OverrideNames::options()) const;
  // What nuld render and nuld.render refuse of the overrides as applied
  // (`applied`, from appliedTo): a max depth under an integrator other than
  // path, which traces one bounce whatever the depth. Throws
  // std::invalid_argument "MAX-DEPTH applies to INTEGRATOR path only".
  void checkApplicable(const RenderSettings &applied, const OverrideNames &names) const;
};

// The lobe tables a render with `s` builds: s.lobeTables with the density
// chosen when it is not given, f cos (mix 0) for the BSDF-only estimator and
// the material's sampling pdf (mix 1) for those that weigh BSDF samples
// against light samples by MIS (renderer/lobe_tables.h says why).
LobeTablesConfig lobeTablesFor(const RenderSettings &s);

struct RenderStats {
  double seconds = 0;  // the render, setup excluded
  // Building the lobe tables (first render of a scene) and preparing the
  // backend; of that, the sets the backend made as it prepared
  // (SamplerBackend::setsMadeSeconds).
  double setupSeconds = 0, setsMadeSeconds = 0;
  std::uint64_t rays = 0;
  std::uint64_t rejectedSamples = 0;   // non-finite values dropped
  std::uint64_t classicFallbacks = 0;  // first-bounce lobe contexts the backend declined
  // The lobe tables' view bins, and those whose route is the table
  // (LobeTables::routes); 0 when the backend samples no lobes.
  // Lobe table bins: all, and those a table serves.
  std::size_t lobeBins = 0, lobeBinsTabulated = 0;
  double raysPerSecond() const { return seconds > 0 ? rays / seconds : 0; }
};

// What a render's files say about it (EXR and PNG attributes, "nuld:" names):
// the scene's name, its materials' lobe choice (Scene::lobeChoice) and its
// environment's importance, backend, seed, spp, integrator, resolution, max
// depth, the lobe tables' settings, render and setup seconds, the renderer's
// revision and the program's version.
ImageAttributes renderAttributes(const std::string &sceneName, const Scene &scene,
                                 const RenderSettings &s, const std::string &backend,
                                 std::uint64_t seed, const RenderStats &stats);

// Called after each finished tile with (tiles done, tiles in all); calls are
// serialized.
using RenderProgress = std::function<void(std::size_t, std::size_t)>;

// Returns a linear RGB image (3 channels, row 0 at the top). With `rays`,
// every traced ray is recorded (for benchmarks; the order across threads is
// unspecified).
Image render(const Scene &scene, const RenderSettings &settings, SamplerBackend &backend,
             RenderStats *stats = nullptr, const RenderProgress &progress = {},
             std::vector<RecordedRay> *rays = nullptr);

}  // namespace nuld
