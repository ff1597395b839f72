#pragma once
// From a backend word to a backend ready to render (docs/architecture.md,
// "From a backend word to samples"): the word parsed, the sets it needs
// made or found in the set cache (set_cache.h), and the backend made. The
// one path every command that renders takes; the studies plan many cells'
// sets at once through set_plans.h, the same mechanism.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "backends/backend_registry.h"
#include "backends/optimized_sets.h"
#include "renderer/render.h"
#include "renderer/sampler_backend.h"
#include "renderer/scene.h"
#include "sampler/optimize/optimizer.h"

namespace nuld {

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
  // time (tools/experiments/setup_nested_sets.md).
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
  // The set cache's directory (backends/set_cache.h); empty:
  // SetCache::fromEnvironment ($NULD_CACHE, ...).
  std::filesystem::path cacheDir;

  // Throws std::invalid_argument naming the bad option.
  void validate() const;
};

// Progress of making sets, for a progress bar: a task label ("optimize
// sets"), the fraction of it done and a short status.
using SetProgress =
    std::function<void(const std::string &task, double fraction, const std::string &status)>;

// A backend word as a command takes it (--backend, --backends, Python's
// backend), parsed once by the registry: what renders with it, and the sets
// a command makes first (optimized, optimized-uniform, optimized-bsdf,
// optimized-both, each maybe with +shift).
//
// A study's row may carry a label: "LABEL=WORD" (LABEL of letters, digits
// and - _ . +), which names the row in tables, files and pages in place of
// a long word (a plugin's path); the row is the word's in every other way.
struct BackendWord {
  std::string word;   // as given, label included: a study's backend column
  std::string label;  // the row's name: LABEL, or the word when unlabelled
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
BackendWord parseBackendWord(const std::string &word);
// The label of a backend column's value ("LABEL=WORD"), or the value when
// it has none; the word after it. No backend is parsed.
std::string rowLabel(const std::string &word);
std::string unlabelled(const std::string &word);

// A word's sets for one render (nuld render, nuld bank, the Python module):
// made or found in the set cache exactly as a study would make them (the
// --opt-* settings and cache), and the spec of the backend that serves
// them. A word that makes no sets passes through unchanged.
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
PreparedBackend prepareBackend(const BackendWord &word, const Scene &scene,
                               const RenderSettings &settings, const std::string &sceneName,
                               const SetSettings &sets, std::uint64_t seed,
                               const std::vector<std::size_t> &sppFamily = {},
                               const SetProgress &progress = {});

// The one factory from a word, a scene and its render settings to a backend
// ready to render: its sets prepared (prepareBackend), then the backend
// made and seeded (makeBackend). nuld render, nuld bank and Python's render
// call it; a study plans many cells' sets at once (set_plans.h) and makes
// each repeat's backend from the planned spec.
struct ReadyBackend {
  std::unique_ptr<SamplerBackend> backend;
  PreparedBackend prepared;
};
ReadyBackend makeReadyBackend(const BackendWord &word, const Scene &scene,
                              const RenderSettings &settings, const std::string &sceneName,
                              const SetSettings &sets, std::uint64_t seed,
                              const std::vector<std::size_t> &sppFamily = {},
                              const SetProgress &progress = {});

// A file-name-safe form of a scene or backend name: "neural:m/q.nuldnet" ->
// "neural-q", "scenes/cup.json" -> "cup".
std::string slug(const std::string &name);

}  // namespace nuld
