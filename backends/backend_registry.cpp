#include "backends/backend_registry.h"

#include <algorithm>
#include <stdexcept>

#include "backends/bank_backend.h"
#include "backends/neural_backend.h"
#include "backends/plugin_backend.h"
#include "sampler/bluenoise/blue_noise_sets.h"
#include "sampler/enum_names.h"

namespace nuld {

const std::vector<BackendEntry> &backendRegistry() {
  using K = BackendKind;
  using S = BackendSets;
  // The blue-noise words are the sampler's own names for its methods.
  const auto blueNoise = [](K kind, BlueNoiseMethod method, bool mapped, const char *help) {
    return BackendEntry{.kind = kind,
                        .name = std::string(kBlueNoiseNames.name({method, mapped})),
                        .help = help,
                        .uses = kIntegration};
  };
  static const std::vector<BackendEntry> registry{
      {.kind = K::Independent,
       .name = "independent",
       .aliases = {"random"},
       .help = "independent uniform points; the map's inverse CDF for light samples, the "
               "material's lobe-selection mapping for BSDF samples"},
      {.kind = K::IndependentTabulated,
       .name = "independent-tabulated",
       .help = "independent, with BSDF samples through the tabulated lobe as sobol-tabulated",
       .lobes = true},
      {.kind = K::Sobol,
       .name = "sobol",
       .help = "Owen-scrambled Sobol per pixel and pair, mapped as independent (the paper's "
               "baseline)"},
      {.kind = K::SobolTabulated,
       .name = "sobol-tabulated",
       .help = "sobol, with first-bounce BSDF samples through the tabulated lobe's "
               "inverse CDF where the view bin's measured route is the table (the "
               "classic baseline for BSDF sampling; --lobe-mix, --lobe-routes)",
       .lobes = true},
      {.kind = K::Halton, .name = "halton", .help = "Owen-scrambled Halton, mapped as independent"},
      {.kind = K::HaltonTabulated,
       .name = "halton-tabulated",
       .help = "halton, with BSDF samples through the tabulated lobe as sobol-tabulated",
       .lobes = true},
      {.kind = K::Stratified,
       .name = "stratified",
       .aliases = {"jittered"},
       .help = "jittered: one uniform point in each cell of a square grid per pixel and pair "
               "(pbrt-v4's StratifiedSampler, Mitsuba's stratified); spp that are not a "
               "square take distinct random cells of the next square grid"},
      {.kind = K::Pmj02,
       .name = "pmj02",
       .help = "progressive multi-jittered (0,2) sets (Christensen, Kensler and Kilpatrick "
               "2018, made by Pharr's 2019 method; RenderMan's and Cycles' PMJ), "
               "Owen-scrambled per pixel and pair: every power-of-two prefix a (0,2)-net"},
      {.kind = K::ZSobol,
       .name = "zsobol",
       .help = "one Owen-scrambled Sobol sequence over the image, each pixel's block at its "
               "Morton code with random base-4 digit permutations, so that error spreads "
               "as blue noise over the screen (Ahmed and Wonka 2020, as pbrt-v4's "
               "ZSobolSampler)",
       .uses = kRenders},
      {.kind = K::SobolFull,
       .name = "sobol-full",
       .help = "the domains of a path take consecutive dimensions of one Owen-scrambled Sobol "
               "sequence per pixel (pbrt-v4's SobolSampler over the pixel's samples; "
               "sobol pads each domain instead), so camera, light and BSDF numbers are "
               "stratified together; domains past Sobol's 25th dimension are padded",
       .uses = kRenders},
      {.kind = K::Lattice,
       .name = "lattice",
       .help = "a rank-1 lattice (the best-separated generator coprime with N up to 65536 "
               "points, the Fibonacci rule beyond) Cranley-Patterson shifted per pixel and "
               "pair"},
      {.kind = K::LatticeBaker,
       .name = "lattice-baker",
       .help = "lattice, each coordinate then folded by the baker's transform "
               "x -> 1 - |2x - 1| (Hickernell 2002), so that smooth integrands that are not "
               "periodic converge as periodic ones do under a lattice rule"},
      {.kind = K::Optimized,
       .name = "optimized",
       .aliases = {"points"},
       .argument = "PATHS",
       .help = "point-set files or directories (comma-separated): sets for the "
               "scene's map, lobe tables or the uniform target serve the first "
               "bounce; everything else is sobol. Without PATHS: sets optimized "
               "for the scene's environment map (light samples) or, in study "
               "integrate, for each integrand's target, made once and kept in "
               "the set cache",
       .lobes = true,
       .setBounces = 1,
       .optionalArgument = true,
       .makes = S::EnvMap,
       .shiftable = true},
      {.kind = K::OptimizedUniform,
       .name = "optimized-uniform",
       .help = "uniform sets made for the periodic L2 discrepancy (primary samples)",
       .lobes = true,
       .setBounces = 1,
       .uses = kRenders,
       .makes = S::Uniform,
       .shiftable = true},
      {.kind = K::OptimizedBsdf,
       .name = "optimized-bsdf",
       .help = "lobe banks made for the scene's Disney materials (BSDF samples)",
       .lobes = true,
       .setBounces = 1,
       .uses = kRenders,
       .makes = S::Lobes,
       .shiftable = true},
      {.kind = K::OptimizedBoth,
       .name = "optimized-both",
       .help = "optimized and optimized-bsdf together",
       .lobes = true,
       .setBounces = 1,
       .uses = kRenders,
       .makes = S::EnvMapAndLobes,
       .shiftable = true},
      {.kind = K::Shifted,
       .name = "shifted",
       .argument = "PATHS",
       .help = "optimized:PATHS with every set Cranley-Patterson shifted in primary "
               "space per pixel and pair (unbiased)",
       .lobes = true,
       .setBounces = 1},
      {.kind = K::Neural,
       .name = "neural",
       .aliases = {"neural-bsdf"},
       .argument = "MODEL",
       .help = "sets a trained model (nuld train) generates for the map or, for a "
               "family:disney model, for each lobe table (those shifted in primary "
               "space); the first bounce. Without MODEL: the shipped Disney-family "
               "model (models/README.md), which serves every scene's lobe tables "
               "with no per-scene setup",
       .lobes = true,
       .setBounces = 1,
       .optionalArgument = true,
       .shiftable = true},
      {.kind = K::Plugin,
       .name = "plugin",
       .argument = "PATH[:ARGS]",
       .help = "your own sampler: a shared library built against plugins/nuld_sampler.h "
               "alone, given ARGS (plugins/README.md); it serves every bounce's pairs, "
               "or the first ones it says, the rest are sobol",
       .uses = kRenders},
      blueNoise(K::Sot, BlueNoiseMethod::SlicedOt, false,
                "sliced optimal transport sets for the integrand's target"),
      blueNoise(K::SotMapped, BlueNoiseMethod::SlicedOt, true,
                "sliced optimal transport sets for the uniform square, mapped by the "
                "target's inverse CDF"),
      blueNoise(K::Gbn, BlueNoiseMethod::Gaussian, false,
                "Gaussian blue noise for the integrand's target"),
      blueNoise(K::GbnMapped, BlueNoiseMethod::Gaussian, true,
                "Gaussian blue noise for the uniform square, mapped by the target's "
                "inverse CDF"),
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
  return (argument.empty() ? e.name : e.name + ":" + argument) + (shift ? "+shift" : "");
}

BackendSets BackendSpec::setsToMake() const {
  return argument.empty() ? entry().makes : BackendSets::None;
}

namespace {

std::string whereServed(const BackendEntry &e) {
  return e.serves(kRenders) ? "renders only (nuld render, nuld bank, study render)"
                            : "the integration study only (study integrate)";
}

constexpr std::string_view kShiftSuffix = "+shift";

}  // namespace

std::string backendSpellings(unsigned use) {
  std::vector<std::string> names;
  for (const BackendEntry &e : backendRegistry())
    if (e.uses & use) names.push_back(e.spelling());
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

BackendSpec parseBackend(const std::string &text, unsigned use) {
  std::string word = text;
  const bool shift = word.size() > kShiftSuffix.size() && word.ends_with(kShiftSuffix);
  if (shift) word.resize(word.size() - kShiftSuffix.size());
  const auto colon = word.find(':');
  const std::string name = word.substr(0, colon);
  for (const BackendEntry &e : backendRegistry()) {
    if (name != e.name && std::find(e.aliases.begin(), e.aliases.end(), name) == e.aliases.end())
      continue;
    const std::string argument = colon == std::string::npos ? "" : word.substr(colon + 1);
    if (e.argument.empty() && colon != std::string::npos)
      throw std::invalid_argument("backend '" + text + "': " + e.name + " takes no argument");
    if (!e.argument.empty() && argument.empty() && !e.optionalArgument)
      throw std::invalid_argument("backend '" + text + "': expected " + e.spelling() +
                                  " (nuld help backends)");
    if (shift && !e.shiftable)
      throw std::invalid_argument(
          "backend '" + text + "': +shift applies to the words whose " +
          "sets it can shift (optimized, optimized-uniform, " +
          "optimized-bsdf, optimized-both, neural)" +
          (e.kind == BackendKind::Shifted ? "; shifted is shifted already" : ""));
    if (!(e.uses & use))
      throw std::invalid_argument("backend '" + text + "': " + e.name + " serves " +
                                  whereServed(e));
    // A file's sets shifted are the shifted backend.
    if (shift && e.kind == BackendKind::Optimized && !argument.empty())
      return {BackendKind::Shifted, argument, false};
    return {e.kind, argument, shift};
  }
  throw std::invalid_argument("unknown backend '" + text + "'" + didYouMean(name, backendWords()) +
                              ": expected " + backendSpellings(use) +
                              " (the words that make or name sets, and neural, also with "
                              "+shift; nuld help backends)");
}

std::unique_ptr<SamplerBackend> makeBackend(const BackendSpec &spec, std::uint64_t seed) {
  const BackendEntry &e = spec.entry();
  if (!e.serves(kRenders))
    throw std::invalid_argument("backend '" + spec.text() + "' serves " + whereServed(e));
  if (spec.setsToMake() != BackendSets::None)
    throw std::invalid_argument("backend '" + spec.text() +
                                "' makes its sets for a scene first: nuld render, nuld bank "
                                "and nuld study render do (or name the sets: optimized:PATHS)");
  switch (spec.kind) {
    case BackendKind::Optimized:
    case BackendKind::Shifted:
      return std::make_unique<BankBackend>(spec.text(), loadSetBanks(spec.argument), seed,
                                           0x6f7074696d697a65ull,
                                           spec.kind == BackendKind::Shifted);
    case BackendKind::Neural:
      return std::make_unique<NeuralBackend>(
          spec.text(), spec.argument.empty() ? shippedLobeModel() : spec.argument, seed,
          spec.shift);
    case BackendKind::Plugin:
      return std::make_unique<PluginBackend>(spec.text(), spec.argument, seed);
    default: return makeClassicBackend(spec.kind, seed);
  }
}

std::unique_ptr<SamplerBackend> makeBackend(const std::string &word, std::uint64_t seed) {
  return makeBackend(parseBackend(word), seed);
}

}  // namespace nuld
