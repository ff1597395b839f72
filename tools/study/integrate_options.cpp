// `nuld study integrate`'s options: the N list, the sampler choices and the
// integrands they select (with the environment maps those need).

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "backends/backend_registry.h"
#include "backends/neural_backend.h"
#include "sampler/enum_names.h"
#include "sampler/targets/target_spec.h"
#include "scenes/default_scene.h"
#include "tools/study/integrate_internal.h"
#include "tools/study/integration_study.h"

namespace nuld::study {
namespace fs = std::filesystem;

namespace {

// A built-in map name (no file): the default sky with a 1e6 sun.
constexpr const char *kSunMap = "sun";

std::optional<std::string> findEnvmap(const std::string &root, const std::string &name) {
  std::vector<fs::path> candidates;
  const fs::path dir = fs::path(root) / "envmaps";
  if (fs::path(name).has_extension() || name.find('/') != std::string::npos)
    candidates = {fs::path(name), dir / name, fs::path(root) / name};
  else
    for (const char *suffix : {"_latlong.exr", "_latlong.hdr", ".exr", ".hdr"})
      candidates.push_back(dir / (name + suffix));
  for (const auto &c : candidates)
    if (fs::is_regular_file(c)) return c.string();
  return std::nullopt;
}

std::string envmapShortName(const std::string &name) {
  if (!fs::path(name).has_extension() && name.find('/') == std::string::npos) return name;
  std::string stem = fs::path(name).stem().string();
  if (stem.size() > 8 && stem.ends_with("_latlong")) stem.resize(stem.size() - 8);
  return stem;
}

}  // namespace

std::vector<std::string> splitList(const std::string &text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
  }
  return out;
}

std::vector<std::size_t> parseNList(const std::string &text) { return parseSizeList("--n", text); }

std::vector<SamplerChoice> parseSamplers(const std::vector<std::string> &tokens,
                                         const std::vector<std::string> &models) {
  using K = SamplerChoice::Kind;
  using B = BackendKind;
  const std::vector<std::string> defaults{
      "independent", "independent-tabulated", "sobol",      "sobol-tabulated",
      "halton",      "halton-tabulated",      "stratified", "pmj02",
      "lattice",     "lattice-baker",         "optimized"};
  std::vector<SamplerChoice> out;
  const auto add = [&](SamplerChoice c) {
    for (const auto &o : out) {
      if (o.name != c.name) continue;
      if (o.model != c.model)
        throw std::invalid_argument("--neural: models '" + o.model + "' and '" + c.model +
                                    "' would both be named '" + c.name + "' (rename one file)");
      return;
    }
    out.push_back(std::move(c));
  };
  // A model's row, named by the file's stem (the CSV does not carry this
  // machine's paths).
  const auto addModel = [&](const std::string &model, bool shifted) {
    if (model.empty()) throw std::invalid_argument("--neural: empty model path");
    add({"neural:" + fs::path(model).stem().string() + (shifted ? "+shift" : ""),
         K::Neural,
         false,
         model,
         {},
         shifted});
  };
  std::vector<std::pair<std::string, bool>> modelList;  // after every other row
  for (const std::string &t : tokens.empty() ? defaults : tokens) {
    if (t.ends_with("-lobes"))
      throw std::invalid_argument(
          "--samplers: '" + t + "' is now '" + t.substr(0, t.size() - 6) +
          "' (each sampler's own mapping: the BRDF's sample() on lobe integrands, as in nuld "
          "render); the tabulated lobe's inverse CDF is '" +
          t.substr(0, t.size() - 6) + "-tabulated'");
    BackendSpec spec;
    try {
      spec = parseBackend(t, kIntegration);
    } catch (const std::invalid_argument &e) {
      throw std::invalid_argument(std::string("--samplers: ") + e.what());
    }
    const std::string name = spec.entry().name;
    const auto classic = [&](SequenceKind sequence, bool tabulated,
                             std::optional<Scramble> scramble = std::nullopt) {
      SamplerChoice c{name, K::Classic, tabulated};
      c.sequence = sequence;
      c.scramble = scramble.value_or(defaultScramble(sequence));
      return c;
    };
    // Each classic sampler in its own mapping (a lobe integrand's BRDF
    // sample(), any other target's inverse CDF) or, -tabulated, through the
    // tabulated lobe's inverse CDF: the meanings renders give the words.
    switch (spec.kind) {
      case B::Independent: add(classic(SequenceKind::Random, false)); break;
      case B::IndependentTabulated: add(classic(SequenceKind::Random, true)); break;
      case B::Sobol: add(classic(SequenceKind::Sobol, false)); break;
      case B::SobolTabulated: add(classic(SequenceKind::Sobol, true)); break;
      case B::Halton: add(classic(SequenceKind::Halton, false)); break;
      case B::HaltonTabulated: add(classic(SequenceKind::Halton, true)); break;
      case B::Stratified: add(classic(SequenceKind::Stratified, false)); break;
      case B::Pmj02: add(classic(SequenceKind::Pmj02, false)); break;
      case B::Lattice: add(classic(SequenceKind::Lattice, false)); break;
      case B::LatticeBaker: add(classic(SequenceKind::Lattice, false, Scramble::Baker)); break;
      case B::Sot:
      case B::SotMapped:
      case B::Gbn:
      case B::GbnMapped: add({name, K::BlueNoise, false, {}, {}, false}); break;
      case B::Neural:
        modelList.emplace_back(spec.argument.empty() ? shippedLobeModel() : spec.argument,
                               spec.shift);
        break;
      case B::Optimized:
      case B::Shifted: {
        if (spec.argument.empty()) {
          if (spec.shift)
            throw std::invalid_argument("--samplers: '" + t +
                                        "': the study's optimized sets are made for each "
                                        "integrand's target and dealt as made; +shift applies to "
                                        "banks from files (shifted:PATHS) and models");
          add({name, K::Optimized, false, {}, {}, false});
          break;
        }
        // Named by the files' stems, as neural models are.
        std::string row = name + ":";
        std::stringstream paths(spec.argument);
        for (std::string path; std::getline(paths, path, ',');) {
          if (row.back() != ':') row += ',';
          row += fs::path(path).stem().string();
        }
        add({row, K::Bank, false, {}, spec.argument, spec.kind == B::Shifted});
        break;
      }
      default: throw std::logic_error("parseSamplers: an integration word without a sampler");
    }
  }
  for (const std::string &m : models) modelList.emplace_back(m, false);
  for (const auto &[m, shifted] : modelList) addModel(m, shifted);
  return out;
}

std::vector<Integrand> selectIntegrands(const IntegrateOptions &o,
                                        std::vector<std::string> &notes) {
  const auto &kinds = integrandKinds();
  const auto wants = [&](const std::string &kind, const std::string &fullName) {
    if (o.integrands.empty()) return true;
    for (const auto &t : o.integrands)
      if (t == "all" || t == kind || t == fullName) return true;
    return false;
  };
  // Every token must name a kind or an integrand the maps make.
  std::vector<std::string> known = kinds;
  for (const auto &m : o.envmaps) {
    known.push_back("envmap:" + envmapShortName(m) + "*cos");
    known.push_back("disney*envmap:" + envmapShortName(m));
    known.push_back("disney-grazing*envmap:" + envmapShortName(m));
    for (double theta : disneyViewThetas())
      known.push_back(disneyViewName(envmapShortName(m), theta));
  }
  for (double theta : disneyCosinesThetas()) known.push_back(disneyCosinesName(theta));
  for (const auto &t : o.integrands)
    if (t != "all" && std::find(known.begin(), known.end(), t) == known.end())
      throw std::invalid_argument("--integrands: unknown integrand '" + t + "' (expected " +
                                  joinNames(known) + ")");

  std::vector<Integrand> out;
  if (wants(kinds[0], kinds[0])) out.push_back(makeGaussianStep());
  if (wants(kinds[1], kinds[1])) out.push_back(makeQuarterDiscBilinear());
  for (const auto &m : o.envmaps) {
    const std::string name = envmapShortName(m);
    const bool cosine = wants(kinds[2], "envmap:" + name + "*cos");
    const bool disney = wants(kinds[3], "disney*envmap:" + name);
    const bool grazing = wants(kinds[4], "disney-grazing*envmap:" + name);
    std::vector<double> views;
    for (double theta : disneyViewThetas())
      if (wants(kinds[6], disneyViewName(name, theta))) views.push_back(theta);
    if (!cosine && !disney && !grazing && views.empty()) continue;
    std::shared_ptr<const StudyEnvmap> map;
    if (m == kSunMap) {
      // The stability case: the default scene's sky with a sun 1e6 times
      // brighter than its sky, built in so it needs no file.
      map = makeStudyEnvmap(proceduralSky(512, 256, 1e6), m, "procedural-sun-1e6");
    } else if (const auto path = findEnvmap(o.assetRoot, m)) {
      map = loadStudyEnvmap(*path, name);
    } else {
      const std::string why = "no file " + m + "_latlong.exr/.hdr or " + m + ".exr/.hdr in " +
                              (fs::path(o.assetRoot) / "envmaps").string();
      // A map the user named must exist (a typo must not leave a table
      // without its rows); the default map is skipped with a note where the
      // assets are missing.
      if (o.envmapsNamed) {
        std::vector<std::string> there;
        std::error_code ec;
        for (const auto &e : fs::directory_iterator(fs::path(o.assetRoot) / "envmaps", ec)) {
          std::string stem = e.path().stem().string();
          if (stem.ends_with("_latlong")) there.push_back(stem.substr(0, stem.size() - 8));
        }
        std::sort(there.begin(), there.end());
        throw std::invalid_argument(
            "--envmaps '" + m + "': " + why + didYouMean(m, there) +
            (there.empty() ? " (check --assets)" : " (maps there: " + joinNames(there) + ")"));
      }
      notes.push_back("skipping the integrands of environment map '" + m + "': " + why +
                      " (check --assets)");
      continue;
    }
    if (cosine) out.push_back(makeEnvmapCos(map));
    if (disney)
      out.push_back(makeDisneyEnvmap(map, supplementDisneyParams(), supplementWo(), o.lobeChoice));
    if (grazing) {
      Integrand in = makeDisneyEnvmap(map, supplementDisneyParams(), grazingWo(), o.lobeChoice);
      in.name = "disney-grazing*envmap:" + name;
      out.push_back(std::move(in));
    }
    for (double theta : views) {
      DisneyTargetSpec view;  // the supplement's instance at theta, phi 0
      view.thetaDegrees = theta;
      Integrand in = makeDisneyEnvmap(map, view.params, view.wo(), o.lobeChoice);
      in.name = disneyViewName(name, theta);
      out.push_back(std::move(in));
    }
  }
  for (double theta : disneyCosinesThetas())
    if (wants(kinds[5], disneyCosinesName(theta)))
      out.push_back(makeDisneyCosines(theta, supplementDisneyParams(), o.lobeChoice));
  for (const auto &in : out) {
    notes.push_back(in.name + ": reference " + formatPrecise(in.reference) + " (" +
                    in.referenceMethod + "; estimated error " +
                    formatNumber(in.referenceError / std::abs(in.reference)) + " relative)");
    if (in.referenceError > 1e-7 * std::abs(in.reference))
      notes.push_back("warning: the reference of " + in.name + " has converged only to " +
                      formatNumber(in.referenceError / std::abs(in.reference)) + " relative");
  }
  return out;
}

}  // namespace nuld::study
