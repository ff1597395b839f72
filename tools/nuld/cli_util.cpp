#include "tools/nuld/cli_util.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <stdexcept>

#include "backends/set_cache.h"
#include "sampler/diagnostics.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/io/round_trip.h"
#include "sampler/optimize/optimizer.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/target_spec.h"

namespace nuld::cli {

std::unique_ptr<Target> targetFor(const std::string &spec, const PointSet &set,
                                  const std::string &file) {
  const std::string *recorded = findMeta(set, meta::kTarget);
  const std::string *hash = findMeta(set, meta::kTargetHash);
  if (!spec.empty()) {
    auto target = makeTarget(spec);
    // The recorded map under another path: said, so a mismatch is not
    // taken for the set's quality.
    if (recorded && hash && !followsTarget(set, target->spec(), target->contentHash()))
      warning(file + ": its points were made for '" + *recorded + "' (content " + *hash +
              "), which is not the density of --target '" + spec + "' (content " +
              target->contentHash() + ")");
    return target;
  }
  if (!recorded) return std::make_unique<UniformTarget>();
  try {
    return makeTarget(*recorded);
  } catch (const std::runtime_error &e) {
    // A set made on another machine or under another asset root names a
    // path that is not here; its content hash still identifies the map.
    throw std::runtime_error(file + ": its target '" + *recorded + "' cannot be opened here (" +
                             e.what() + "); pass --target naming the same map under this " +
                             "machine's asset root" +
                             (hash ? " (checked by its content hash " + *hash + ")" : ""));
  }
}

void mapByInverseCdf(PointSet &set, const Target &target) {
  if (!target.hasInverse())
    throw std::invalid_argument("target '" + target.spec() +
                                "' has no inverse CDF to map points with");
  for (Point2 &p : set.points) p = target.invert(p).x;
  recordTarget(set, target);
  setMeta(set, meta::kMapping, std::string(meta::kInverseCdf));
}

Resolution parseResolution(const std::string &text) {
  static const std::regex re(R"((\d{1,9})(?:x(\d{1,9}))?)");
  std::smatch m;
  if (!std::regex_match(text, m, re))
    throw std::invalid_argument("'" + text + "': expected W or WxH, e.g. 512 or 640x480");
  Resolution r;
  r.width = std::stoi(m[1]);
  r.height = m[2].matched ? std::stoi(m[2]) : 0;  // 0: the scene's aspect
  if (r.width < 1 || (m[2].matched && r.height < 1) || r.width > 32768 || r.height > 32768)
    throw std::invalid_argument("'" + text + "': each side must be in [1, 32768]");
  return r;
}

void applyResolution(const CLI::App &app, const std::string &res, double scale,
                     RenderOverrides &change) {
  onlyWhen(app, res.empty(), {"--res-scale"}, "renders at a scene's own resolution (no --res)");
  if (!res.empty()) {
    const Resolution r = parseResolution(res);
    change.width = r.width;
    if (r.height) change.height = r.height;
  }
  change.resolutionScale = scale;
}

void addRunFlags(CLI::App &app, RunFlags &flags, const std::string &unit,
                 const std::string &alsoDoes) {
  app.add_option("--checkpoint-every", flags.checkpointEvery,
                 unit + "s between checkpoints" + alsoDoes + " (default: about every 5 %)")
      ->check(positiveNumber());
  auto *resume = app.add_flag("--resume", flags.resume, "continue from OUTPUT.ckpt if it exists");
  app.add_flag("--fresh", flags.fresh,
               "start over even if OUTPUT.ckpt exists, replacing it (without --resume or "
               "--fresh an existing checkpoint is an error)")
      ->excludes(resume);
  app.add_option("--stop-after", flags.stopAfter, "stop (with a checkpoint) after this " + unit)
      ->check(nonNegativeNumber());
  app.add_flag("-q,--quiet", flags.quiet, "no progress bar or messages (results still print)");
}

CLI::Validator wholeNumber() {
  return CLI::Validator(
      [](std::string &text) {
        std::uint64_t value = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (!text.empty() && ec == std::errc() && end == text.data() + text.size())
          return std::string();
        return "expected a whole number from 0 to 2^64 - 1, got '" + text + "'";
      },
      "UINT");
}

namespace {

// 2^k for the large powers of two the options use as bounds, else digits.
std::string boundText(std::int64_t v) {
  if (v >= (std::int64_t(1) << 20) && (v & (v - 1)) == 0)
    return "2^" + std::to_string(std::countr_zero(std::uint64_t(v)));
  return std::to_string(v);
}

CLI::Validator numberAbove(bool allowZero) {
  return CLI::Validator(
      [allowZero](std::string &text) {
        double value = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (ec == std::errc() && end == text.data() + text.size() && std::isfinite(value) &&
            (value > 0 || (allowZero && value == 0)))
          return std::string();
        return std::string(allowZero ? "expected a number >= 0" : "expected a number > 0") +
               ", got '" + text + "'";
      },
      allowZero ? "NUMBER >= 0" : "NUMBER > 0");
}

}  // namespace

CLI::Validator wholeNumberIn(std::int64_t lo, std::int64_t hi) {
  const std::string range = boundText(lo) + " to " + boundText(hi);
  return CLI::Validator(
      [lo, hi, range](std::string &text) {
        std::int64_t value = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (!text.empty() && ec == std::errc() && end == text.data() + text.size() && value >= lo &&
            value <= hi)
          return std::string();
        return "expected a whole number from " + range + ", got '" + text + "'";
      },
      "INT in " + range);
}

CLI::Validator numberIn(double lo, double hi) {
  const std::string range = "[" + formatShort(lo) + ", " + formatShort(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string &text) {
        double value = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (ec == std::errc() && end == text.data() + text.size() && value >= lo && value <= hi)
          return std::string();
        return "expected a number in " + range + ", got '" + text + "'";
      },
      "NUMBER in " + range);
}

CLI::Validator positiveNumber() { return numberAbove(false); }
CLI::Validator nonNegativeNumber() { return numberAbove(true); }

void checkAssets(const CLI::App &app, const std::string &assets, bool used,
                 const std::string &when) {
  onlyWhen(app, used, {"--assets"}, when);
  if (app.count("--assets") && !std::filesystem::is_directory(assets))
    throw std::invalid_argument("--assets '" + assets + "': no such directory");
}

void onlyWhen(const CLI::App &app, bool applies, std::initializer_list<const char *> options,
              const std::string &when) {
  if (applies) return;
  // "study render", not just "render".
  std::string command = app.get_name();
  for (const CLI::App *p = app.get_parent(); p && p->get_parent(); p = p->get_parent())
    command = p->get_name() + " " + command;
  for (const char *option : options)
    if (app.count(option))
      throw UsageError(command + ": " + option + " applies to " + when + " only");
}

std::string targetOptionHelp(const std::string &what) {
  std::string list;
  for (const TargetDescription &d : targetDescriptions())
    list += (list.empty() ? "" : ", ") + d.grammar;
  return what + ": " + list + " (nuld help targets)";
}

void addLobeChoiceOption(CLI::App &app, LobeChoice &choice) {
  addNamedOption(app, "--lobe-choice", choice, kLobeChoiceNames,
                 "how Disney materials pick the lobe they sample, at every bounce and in "
                 "references: albedo (by each lobe's reflectance estimated at the view, as "
                 "Cycles; the default), weight (by Mitsuba 3's static weights) or uniform (each "
                 "lobe alike: the paper's configuration, with --env-importance luminance)");
}

void addSceneChoiceOptions(CLI::App &app, SceneChoices &choices) {
  addLobeChoiceOption(app, choices.lobes);
  addNamedOption(app, "--env-importance", choices.importance, kImportanceNames,
                 "what weighs the environment map's sampling density, in place of the scene's: "
                 "luminance (the paper's), mean (of the channels), or either less the map's "
                 "mean over the sphere, luminance-compensated (the default of scenes that name "
                 "none) or mean-compensated; the light integrator samples a compensated map "
                 "without its compensation");
}

void addLobeOptions(CLI::App &app, RenderOverrides &change) {
  app.add_option("--lobe-mix", change.lobeMix,
                 "density of the lobe tables that sobol-tabulated and lobe banks sample: 0 f "
                 "cos, 1 the material's own sampling pdf, between a mixture (default: 0 for "
                 "--integrator bsdf, 1 under MIS)")
      ->check(numberIn(0, 1));
  addNamedOption(app, "--lobe-routes", change.lobeRouting, kLobeRoutingNames,
                 "how each view bin samples its lobe: measured (the material's own sampler or "
                 "the bin's table, whichever measures best; the default) or table (every bin its "
                 "table)");
  app.add_option("--lobe-defensive", change.lobeDefensive,
                 "share of tabulated samples drawn by the material's own sampler; weights are "
                 "then at most 1/share times the material's (default 0: the measured routes guard "
                 "the tables)")
      ->check(numberIn(0, 1));
  app.add_option("--lobe-bounces", change.lobeBounces,
                 "how many bounces, from the first, sample lobe tables (default 1; 0: every "
                 "bounce)")
      ->check(wholeNumberIn(0, kMaxDepthLimit));
}

std::string setsDirectory(const SetSettings &s) {
  return (s.cacheDir.empty() ? SetCache::fromEnvironment() : SetCache(s.cacheDir))
      .setsDir()
      .string();
}

std::string setsInterruptNote(const std::string &setsDir) {
  return "the sets being made keep their checkpoints in " + setsDir +
         " (the set cache): run the same command again to continue them";
}

void addSetOptions(CLI::App &app, SetSettings &s) {
  app.add_option("--opt-instances", s.instances,
                 "instances of the optimized backends' sets (default 16, as the paper)")
      ->check(positiveNumber());
  const auto epochsOf = [](const char *preset) {
    return std::to_string(presetSettings(preset, 16).epochs);
  };
  app.add_option("--opt-epochs", s.epochs,
                 "epochs of the map's and the uniform sets' optimization (default: the "
                 "preset's: " +
                     epochsOf("sphere-exact") + " for the map's sets (" + epochsOf("sphere") +
                     " under --opt-objective soft), " + epochsOf("uniform") +
                     " for optimized-uniform)")
      ->check(positiveNumber());
  app.add_option("--opt-lobe-epochs", s.lobeEpochs,
                 "epochs of the lobe banks (default: --opt-epochs if given, else 250)")
      ->check(positiveNumber());
  app.add_flag("--opt-nested", s.nested,
               "one nested bank per target at the largest --spp whose prefixes serve the "
               "smaller spp (nuld optimize --nested), instead of a bank per spp; a nested bank "
               "in the set cache that holds a cell's spp serves it with no setup");
  addNamedOption(app, "--opt-objective", s.envObjective, kObjectiveNames,
                 "objective of the environment-map sets: l2asd (the exact grid L2asd with the "
                 "bank term, 500 epochs: nuld optimize --preset sphere-exact) or soft "
                 "(Algorithm 1, the paper's sphere preset, 5000 epochs) (default l2asd; the lobe "
                 "banks always take l2asd)");
  app.add_option("--opt-union-weight", s.unionWeight,
                 "weight of the bank term of every bank optimized for the exact L2asd (the "
                 "lobe banks; the map's sets with --opt-objective l2asd; nuld optimize "
                 "--union-weight), which keeps a glossy lobe's or a sunny map's instances from "
                 "converging to one set (default 3; 0: instances optimized apart)")
      ->check(nonNegativeNumber());
}

CLI::Validator targetFamily() { return parsedBy(checkTargetFamily); }
CLI::Validator backendWord() {
  return parsedBy([](const std::string &word) {
    if (parseBackend(word, kRenders).setsToMake() != BackendSets::None)
      throw std::invalid_argument("backend '" + word +
                                  "' makes its sets first; name a backend that needs none");
  });
}
CLI::Validator studyBackendWord() { return parsedBy(parseBackendWord); }

}  // namespace nuld::cli
