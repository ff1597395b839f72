#pragma once
// The one catalogue of sampler backends (docs/architecture.md, "From a
// backend word to samples"). Each kind is declared once: its word and
// aliases, its argument, its help line and what it serves. A backend word is
// parsed here, once, into a BackendSpec; makeBackend, `nuld help backends`,
// the --backend option's help, the Python module and the studies read this
// table rather than matching strings of their own.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "renderer/sampler_backend.h"
#include "sampler/sequences/rng.h"

namespace nuld {

enum class BackendKind {
  Independent,
  IndependentTabulated,
  Sobol,
  SobolTabulated,
  Halton,
  HaltonTabulated,
  Stratified,
  Pmj02,
  ZSobol,
  SobolFull,  // consecutive dimensions of one Owen-Sobol sequence per pixel
  Lattice,
  LatticeBaker,
  Optimized,         // optimized[:PATHS]: sets from files, or made for the scene's map
  OptimizedUniform,  // made: uniform sets for the periodic L2 discrepancy
  OptimizedBsdf,     // made: lobe banks for the scene's Disney materials
  OptimizedBoth,     // made: optimized and optimized-bsdf together
  Shifted,           // shifted:PATHS
  Neural,
  Plugin,  // plugin:PATH[:ARGS], a user's sampler (plugins/README.md)
  Sot,     // the blue-noise baselines (integration study only)
  SotMapped,
  Gbn,
  GbnMapped,
};

// The sets a command makes (backends/ready_backend.h: prepareBackend, the
// integration study's optimizer) before it samples with a word.
enum class BackendSets { None, EnvMap, Uniform, Lobes, EnvMapAndLobes };

// Where a word serves: renders (nuld render, nuld bank, study render,
// Python's render) and the integration study (study integrate).
enum BackendUse : unsigned { kRenders = 1, kIntegration = 2, kEverywhere = 3 };

struct BackendEntry {
  BackendKind kind;
  std::string name;                  // the canonical word
  std::vector<std::string> aliases;  // other words for it
  std::string argument;              // "" (none), else the argument's name: NAME:ARGUMENT
  std::string help;
  // Whether it can sample the lobe tables' BSDF pairs (banks and models:
  // those their files or family match; SamplerBackend::samplesLobes says
  // whether a made backend does), and for how many bounces from the first
  // its sets serve (0: every; the pairs of deeper bounces get Owen-Sobol
  // primary points). Not the tables' own bounces (LobeTableSettings::
  // bounces): sobol-tabulated serves the bounces the tables are set to.
  bool lobes = false;
  int setBounces = 0;
  // Whether the word may go without its argument (neural: the shipped
  // model; optimized: sets made for the scene); the spec's argument is then
  // empty and the factory supplies it.
  bool optionalArgument = false;
  unsigned uses = kEverywhere;
  // What a command makes first when the argument is left out (or there is
  // none): the sets the word's samples come from.
  BackendSets makes = BackendSets::None;
  // Whether NAME+shift is a word: every set then Cranley-Patterson shifted
  // in the target's primary space (unbiased for any target).
  bool shiftable = false;

  // NAME, NAME:ARGUMENT or, for an optional argument, NAME[:ARGUMENT];
  // the same for an alias as `word`.
  std::string spelling() const { return spelling(name); }
  std::string spelling(const std::string &word) const {
    if (argument.empty()) return word;
    return optionalArgument ? word + "[:" + argument + "]" : word + ":" + argument;
  }
  bool serves(BackendUse use) const { return (uses & use) != 0; }
};

// Every backend kind, in the order `nuld help backends` lists them.
const std::vector<BackendEntry> &backendRegistry();
const BackendEntry &backendEntry(BackendKind kind);

// A backend word, parsed: the kind, its argument (point-set paths, a model
// file) and the suffix +shift.
struct BackendSpec {
  BackendKind kind = BackendKind::Sobol;
  std::string argument;
  bool shift = false;

  const BackendEntry &entry() const { return backendEntry(kind); }
  // The canonical word: NAME or NAME:ARGUMENT (NAME alone for an optional
  // argument left out), then +shift.
  std::string text() const;
  // The sets a command makes before sampling with this word (None: the
  // backend reads what its argument names, or needs nothing).
  BackendSets setsToMake() const;
  friend bool operator==(const BackendSpec &, const BackendSpec &) = default;
};

// The classic backends, each also -tabulated (for bank fallbacks;
// makeBackend for any kind).
std::unique_ptr<SamplerBackend> makeClassicBackend(BackendKind kind, std::uint64_t seed);

// The one parser of backend words. Throws std::invalid_argument quoting the
// word and listing the spellings (an alias parses to its kind; a kind with
// an argument needs a non-empty one unless it is optional, one without
// takes none; +shift only where the entry allows it). `use`: a word that
// does not serve there is refused, naming where it does. optimized:PATHS+shift
// is shifted:PATHS.
BackendSpec parseBackend(const std::string &word, unsigned use = kEverywhere);
// Every word parseBackend knows before a colon: each entry's name and aliases.
std::vector<std::string> backendWords();

// The backend a spec names, seeded. Reads the files a bank or model names
// (throwing naming the file when one cannot be read). A spec whose sets a
// command makes first (setsToMake) or that serves the integration study
// only is refused, saying so.
std::unique_ptr<SamplerBackend> makeBackend(const BackendSpec &spec, std::uint64_t seed);

std::unique_ptr<SamplerBackend> makeBackend(const std::string &word, std::uint64_t seed);

// "independent, sobol, ..., neural[:MODEL]": every spelling of the words
// that serve `use`, for option help and refusals.
std::string backendSpellings(unsigned use = kEverywhere);

}  // namespace nuld
