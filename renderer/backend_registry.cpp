#include "renderer/backend_registry.h"

#include <algorithm>
#include <stdexcept>

#include "renderer/bank_backend.h"
#include "renderer/neural_backend.h"
#include "sampler/enum_names.h"

namespace nuld {

const std::vector<BackendEntry> &backendRegistry() {
  static const std::vector<BackendEntry> registry{
      {BackendKind::Independent,
       "independent",
       {"random"},
       "",
       "independent uniform points; the map's inverse CDF for light samples, the "
       "material's lobe-selection mapping for BSDF samples",
       false,
       0},
      {BackendKind::Sobol,
       "sobol",
       {},
       "",
       "Owen-scrambled Sobol per pixel and pair, mapped as independent (the paper's "
       "baseline)",
       false,
       0},
      {BackendKind::Halton,
       "halton",
       {},
       "",
       "Owen-scrambled Halton, mapped as independent",
       false,
       0},
      {BackendKind::SobolTabulated,
       "sobol-tabulated",
       {},
       "",
       "sobol, with first-bounce BSDF samples through the tabulated lobe's "
       "inverse CDF where the view bin's measured route is the table (the "
       "strongest classic baseline; --lobe-mix, --lobe-routes)",
       true,
       0},
      {BackendKind::Optimized,
       "optimized",
       {"points"},
       "PATHS",
       "point-set files or directories (comma-separated): sets for the "
       "scene's map, lobe tables or the uniform target serve the first "
       "bounce; everything else is sobol",
       true,
       1},
      {BackendKind::Shifted,
       "shifted",
       {},
       "PATHS",
       "optimized:PATHS with every set Cranley-Patterson shifted in primary "
       "space per pixel and pair (unbiased)",
       true,
       1},
      {BackendKind::Neural,
       "neural",
       {"neural-bsdf"},
       "MODEL",
       "sets a trained model (nuld train) generates for the map or, for a "
       "family:disney model, for each lobe table; the first bounce. Without "
       "MODEL: the shipped Disney-family model (models/README.md), which "
       "serves every scene's lobe tables with no per-scene setup",
       true,
       1,
       true},
  };
  return registry;
}

const BackendEntry &backendEntry(BackendKind kind) {
  for (const BackendEntry &e : backendRegistry())
    if (e.kind == kind) return e;
  throw std::logic_error("backend registry: a kind without an entry");
}

std::string BackendSpec::text() const {
  const BackendEntry &e = entry();
  return argument.empty() ? e.name : e.name + ":" + argument;
}

std::string backendSpellings() {
  std::vector<std::string> names;
  for (const BackendEntry &e : backendRegistry()) names.push_back(e.spelling());
  return joinAlternatives(names);
}

std::vector<std::string> backendWords() {
  std::vector<std::string> names;
  for (const BackendEntry &e : backendRegistry()) {
    names.push_back(e.name);
    names.insert(names.end(), e.aliases.begin(), e.aliases.end());
  }
  return names;
}

BackendSpec parseBackend(const std::string &word) {
  const auto colon = word.find(':');
  const std::string name = word.substr(0, colon);
  for (const BackendEntry &e : backendRegistry()) {
    if (name != e.name && std::find(e.aliases.begin(), e.aliases.end(), name) == e.aliases.end())
      continue;
    const std::string argument = colon == std::string::npos ? "" : word.substr(colon + 1);
    if (e.argument.empty() && colon != std::string::npos)
      throw std::invalid_argument("backend '" + word + "': " + e.name + " takes no argument");
    if (!e.argument.empty() && argument.empty() && !e.optionalArgument)
      throw std::invalid_argument("backend '" + word + "': expected " + e.spelling() +
                                  " (nuld help backends)");
    return {e.kind, argument};
  }
  throw std::invalid_argument("unknown backend '" + word + "'" + didYouMean(name, backendWords()) +
                              ": expected " + backendSpellings() + " (nuld help backends)");
}

std::unique_ptr<SamplerBackend> makeBackend(const BackendSpec &spec, std::uint64_t seed) {
  switch (spec.kind) {
    case BackendKind::Independent:
    case BackendKind::Sobol:
    case BackendKind::Halton:
    case BackendKind::SobolTabulated: return makeClassicBackend(spec.kind, seed);
    case BackendKind::Optimized:
    case BackendKind::Shifted:
      return std::make_unique<BankBackend>(spec.text(), loadSetBanks(spec.argument), seed,
                                           0x6f7074696d697a65ull,
                                           spec.kind == BackendKind::Shifted);
    case BackendKind::Neural:
      return std::make_unique<NeuralBackend>(
          spec.text(), spec.argument.empty() ? shippedLobeModel() : spec.argument, seed);
  }
  throw std::logic_error("makeBackend: a kind without a factory");
}

std::unique_ptr<SamplerBackend> makeBackend(const std::string &word, std::uint64_t seed) {
  return makeBackend(parseBackend(word), seed);
}

}  // namespace nuld
