#pragma once
// The render study: for each scene, a resumable high-spp reference, then a
// render per (backend, spp, repeat) compared with it, one CSV row per
// (scene, backend, spp) with MSE and relMSE (mean and standard error over the
// repeats) and the wall time of a render including the backend's own sample
// generation. One-off costs (optimizing the `optimized` sets) are recorded
// separately as setup seconds. Each row is also scored against the
// reference's own noise and the best classic backend (baselines.h), and at
// equal time (equal_time.h).
//
// Study backends: the renderer's `independent`, `sobol`, `halton`,
// `sobol-tabulated`, `neural:MODEL`, `optimized:PATHS` and `shifted:PATHS`, plus four that the
// study makes itself:
//   optimized          sets for the scene's environment map at N = spp (the
//                      exact L2asd with the bank term, preset sphere-exact;
//                      Algorithm 1's soft boxes with --opt-objective soft),
//                      used as distributed light samples at the first bounce
//                      (skipped for scenes without an environment map)
//   optimized-uniform  sets for the uniform target optimized for the periodic
//                      L2 discrepancy (invariant under the toroidal shift the
//                      backend applies per pixel and pair), served as the
//                      first bounce's primary samples
//   optimized-bsdf     a bank per lobe table of the scene's Disney materials
//                      (renderer/lobe_tables.h), optimized for the exact L2asd
//                      objective, for the first bounce's BSDF pair
//   optimized-both     optimized and optimized-bsdf together
// Their sets live in the shared set cache (backends/set_cache.h), keyed
// by content: another study, directory or asset root reuses them.
// Each of these with the suffix `+shift` renders its sets through
// `shifted:PATHS` (randomized in primary space: unbiased).
// A backend that cannot serve a spp (a neural model or a file of another N)
// is skipped for it with the reason.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend_registry.h"
#include "backends/optimized_sets.h"
#include "backends/ready_backend.h"
#include "backends/reference_render.h"
#include "renderer/sampler_backend.h"
#include "scenes/scene_file.h"
#include "tools/study/adaptive_repeats.h"

namespace nuld::study {

struct RenderStudySettings {
  std::vector<std::string> scenes{"default"};  // "default" or scene JSON paths
  std::vector<std::string> backends{"independent", "sobol", "halton", "optimized"};
  std::vector<std::size_t> spp{4, 16, 64};
  std::string assets;  // asset root (see resolveAssetRoot)
  // What the study changes of every scene's render settings (resolution,
  // integrator, depth, the --lobe-* options); its spp is unused (`spp`).
  RenderOverrides render;
  std::size_t repeats = 1;  // of every row; with a target, the first round's
  // With a target standard error, more repeats for the rows whose MSE
  // ratios (to the best classic row and to sobol) are above it, within the
  // budget (tools/study/adaptive_repeats.h).
  RepeatBudget budget;
  std::uint64_t seed = kDefaultSeed;  // of the renders and of the sets; repeat r: seed + r
  // Renders over which a row's setup is spread in total_seconds and
  // equal_time_ratio (tools/study/equal_time.h); changes no render.
  double amortize = 1;
  ReferenceSettings reference;  // its render settings are filled per scene
  // Where the references are kept (backends/reference_cache.h); empty: the
  // reference cache the environment names (ReferenceCache::fromEnvironment).
  std::filesystem::path referenceCacheDir;
  // Stop each reference after this many passes in this run (0: no limit); a
  // scene whose reference is not complete renders no cells.
  std::size_t referenceStopAfter = 0;
  SetSettings sets;
  // How the scenes' Disney materials pick lobes and, when set, the
  // environments' importance, in every row and the references
  // (--lobe-choice, --env-importance).
  SceneChoices choices;
  std::filesystem::path out;

  // Throws std::invalid_argument naming the bad option.
  void validate() const;
  // What a row depends on beyond its scene, backend and spp, as the
  // command's option names ("repeats=1 seed=1 ..."): a rerun asking for
  // other values is refused (CsvTable::requireOptions).
  std::string rowOptions() const;
};

// Progress of the study, for a progress bar: a task label ("default:
// reference", "default: optimize N=16", "default: renders"), the fraction of
// that task done and a short status.
using StudyProgress = SetProgress;

// The CSV's columns, in order (render.csv); units: seconds of wall time.
// The columns computed over the whole table (equalTimeColumns,
// baselineColumns) are renderStudyDerivedColumns: a file written before one
// existed loads with it empty, and the study fills it.
const std::vector<std::string> &renderStudyColumns();
const std::vector<std::string> &renderStudyDerivedColumns();
// references.csv's columns: scene, backend, spp, resolution, integrator,
// variance, relvariance (ReferenceNoise), seconds (this study's: 0 for a
// reference found in the cache), image, made_seconds (its render time),
// cache ("found" or "rendered"), key and entry (the reference cache's).
const std::vector<std::string> &referenceColumns();
// Those an earlier version's references.csv may lack (loaded empty).
const std::vector<std::string> &referenceOptionalColumns();

struct RenderStudyResult {
  std::filesystem::path csv;                      // out/render.csv
  std::vector<std::string> skipped;               // "scene backend spp: reason"
  std::vector<std::string> notes;                 // e.g. the lobe bins left without banks
  std::vector<std::string> referencesIncomplete;  // scenes stopped by referenceStopAfter
  // "scene: cache entry" of each reference found complete in the cache
  // (backends/reference_cache.h): no pass of it was rendered.
  std::vector<std::string> referencesFound;
};

// Runs (or resumes: rows already in out/render.csv are kept and not
// rendered again) the study. Rows are made spp by spp. Under MPI (ranks.h)
// the references are split by passes, then the sets the optimized backends
// need and the cells (backend, spp) by rounds; rank 0 writes every file, and
// the outputs are those of a single process but for the measured times.
RenderStudyResult runRenderStudy(const RenderStudySettings &settings,
                                 const StudyProgress &progress = {});

}  // namespace nuld::study
