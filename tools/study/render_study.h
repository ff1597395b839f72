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
// Their sets live in the shared set cache (tools/study/set_cache.h), keyed
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

#include "renderer/backend_registry.h"
#include "renderer/sampler_backend.h"
#include "scenes/scene_file.h"
#include "tools/study/optimized_sets.h"
#include "tools/study/reference_render.h"

namespace nuld::study {

// How the study's backends make their sets (optimized, optimized-bsdf, ...):
// the --opt-* options and the set cache, the same in a study, nuld render,
// nuld bank and the Python module.
struct SetSettings {
  std::size_t instances = 16;  // --opt-instances
  // --opt-nested: one nested bank per target at the largest spp, whose
  // prefixes serve the smaller ones (optimizer.h, nestedSizes); a nested
  // bank already in the cache that holds a cell's spp serves it.
  bool nested = false;
  int epochs = 0;  // --opt-epochs; 0: the preset's
  // --opt-lobe-epochs (0: `epochs` if set, else kLobeBankEpochs) and the
  // value the lobe banks get.
  int lobeEpochs = 0;
  int lobeBankEpochs() const { return lobeEpochs ? lobeEpochs : epochs ? epochs : kLobeBankEpochs; }
  // The lobe banks' default, far below the sphere preset's (lobe tables are
  // on the hemisphere): about the same render error in a small part of the
  // time (tools/experiments/README.md, "Setup, nested sets and reuse").
  static constexpr int kLobeBankEpochs = 250;
  // --opt-objective: what the environment-map sets minimize: the exact L2asd
  // (the sphere-exact preset, optimizer.h: renders as well as the soft
  // boxes in a small part of their time) or the paper's soft boxes (the
  // sphere preset). The lobe banks always take the exact L2asd.
  Objective envObjective = Objective::ExactL2asd;
  // --opt-union-weight, the bank term of every bank optimized for the exact
  // L2asd (optimizer.h, unionWeight): without it the instances of a glossy
  // lobe's bank, or of a map with a sun, converge to nearly one set.
  double unionWeight = kBankUnionWeight;
  // The set cache's directory (tools/study/set_cache.h); empty:
  // SetCache::fromEnvironment ($NULD_CACHE, ...).
  std::filesystem::path cacheDir;

  // Throws std::invalid_argument naming the bad option.
  void validate() const;
};

struct RenderStudySettings {
  std::vector<std::string> scenes{"default"};  // "default" or scene JSON paths
  std::vector<std::string> backends{"independent", "sobol", "halton", "optimized"};
  std::vector<std::size_t> spp{4, 16, 64};
  std::string assets;  // asset root (see resolveAssetRoot)
  // What the study changes of every scene's render settings (resolution,
  // integrator, depth, the --lobe-* options); its spp is unused (`spp`).
  RenderOverrides render;
  std::size_t repeats = 1;
  std::uint64_t seed = kDefaultSeed;  // of the renders and of the sets
  // Renders over which a row's setup is spread in total_seconds and
  // equal_time_ratio (tools/study/equal_time.h); changes no render.
  double amortize = 1;
  ReferenceSettings reference;  // its render settings are filled per scene
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
using StudyProgress =
    std::function<void(const std::string &task, double fraction, const std::string &status)>;

// The CSV's columns, in order (render.csv); units: seconds of wall time.
// The columns computed over the whole table (equalTimeColumns,
// baselineColumns) are renderStudyDerivedColumns: a file written before one
// existed loads with it empty, and the study fills it.
const std::vector<std::string> &renderStudyColumns();
const std::vector<std::string> &renderStudyDerivedColumns();
// references.csv's columns: scene, backend, spp, resolution, integrator,
// variance, relvariance (ReferenceNoise), seconds, image.
const std::vector<std::string> &referenceColumns();

// A --backends word, parsed once by the backend registry
// (renderer/backend_registry.h): what the study renders with, and the sets
// it makes first (optimized, optimized-uniform, optimized-bsdf,
// optimized-both, each maybe with +shift).
struct StudyBackend {
  std::string word;  // as given: the CSV's backend column
  BackendSpec spec;
  BackendSets sets = BackendSets::None;  // spec.setsToMake(): None renders `spec` as it is
  bool makesSets() const { return sets != BackendSets::None; }
  bool makesEnvSets() const {
    return sets == BackendSets::EnvMap || sets == BackendSets::EnvMapAndLobes;
  }
  bool makesLobeSets() const {
    return sets == BackendSets::Lobes || sets == BackendSets::EnvMapAndLobes;
  }
  // Whether its renders sample the scene's lobe tables: the study's sets
  // but uniform ones (BankBackend::samplesLobes); a file's banks or a model
  // are asked (which loads them).
  bool samplesLobes() const;
};
// The word parsed for renders; throws std::invalid_argument naming the word
// and the choices.
StudyBackend parseStudyBackend(const std::string &word);

struct RenderStudyResult {
  std::filesystem::path csv;                      // out/render.csv
  std::vector<std::string> skipped;               // "scene backend spp: reason"
  std::vector<std::string> notes;                 // e.g. the lobe bins left without banks
  std::vector<std::string> referencesIncomplete;  // scenes stopped by referenceStopAfter
};

// Runs (or resumes: rows already in out/render.csv are kept and not
// rendered again) the study. Rows are made spp by spp. Under MPI (ranks.h)
// the references are split by passes, then the sets the optimized backends
// need and the cells (backend, spp) by rounds; rank 0 writes every file, and
// the outputs are those of a single process but for the measured times.
RenderStudyResult runRenderStudy(const RenderStudySettings &settings,
                                 const StudyProgress &progress = {});

// A backend word of the study's own sets (optimized, optimized-bsdf, ...)
// for a render outside a study (nuld render, nuld bank, the Python module):
// its sets made or found in the set cache exactly as a study would (the
// options' --opt-* settings and cache), and the renderer backend that
// serves them. A renderer word passes through unchanged.
struct PreparedBackend {
  BackendSpec spec;
  double setupSeconds = 0;  // wall time of making what was missing (0: all cached)
  std::size_t setsMade = 0, setsCached = 0;
  struct Set {
    std::string file, target;  // the set's file and its target's spec, shortened
    bool made = false;         // made now (else found in the cache)
  };
  std::vector<Set> sets;  // one per target: the light, each lobe bin
  std::string note;       // lobe bins left without banks, and why
};
// Throws std::invalid_argument naming the word when the scene cannot use it
// (no environment map for `optimized`, no Disney material for lobe banks).
// `seed`: the optimization's (a study's --seed); `sppFamily`: the sample
// counts a nested bank is made for (its largest is the bank's N; empty:
// the render's spp alone).
PreparedBackend prepareStudyBackend(const StudyBackend &backend, const Scene &scene,
                                    const RenderSettings &settings, const std::string &sceneName,
                                    const SetSettings &sets, std::uint64_t seed,
                                    const std::vector<std::size_t> &sppFamily = {},
                                    const StudyProgress &progress = {});

// A file-name-safe form of a scene or backend name: "neural:m/q.nuldnet" ->
// "neural-q", "scenes/cup.json" -> "cup".
std::string slug(const std::string &name);
// What a reference remembers of its scene: the slug, and for a scene file a
// hash of its text, so that a reference rendered before the file changed (a
// map turned upright, a material edited) is refused rather than reused.
std::string sceneIdentity(const std::string &scenePath);

}  // namespace nuld::study
