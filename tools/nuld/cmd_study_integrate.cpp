// nuld study integrate: integration error against N for product integrands
// in 2D and on the sphere, sampler against sampler (tools/study/
// integration_study.h), into OUTDIR/integrate.csv plus plots.

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <optional>

#include "backends/ranks.h"
#include "backends/stopwatch.h"
#include "sampler/sequences/rng.h"
#include "scenes/scene_file.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"
#include "tools/nuld/progress.h"
#include "tools/study/integration_study.h"

namespace nuld::cli {

namespace {

struct IntegrateCliOptions {
  std::string output, integrands, samplers, ns, assets, envmaps = "grace";
  std::vector<std::string> neural;
  std::size_t instances = 128, optimizedInstances = 16, optimizedMaxN = 1024;
  int optEpochs = 0;
  double optUnionWeight = kBankUnionWeight;
  std::string optObjective;
  std::uint64_t seed = kDefaultSeed;
  LobeChoice lobeChoice = kDefaultLobeChoice;
  bool noPlots = false, quiet = false;
  bool envmapsNamed = false;  // --envmaps given
};

// The study's options from the command line's.
study::IntegrateOptions integrateOptions(const IntegrateCliOptions &o) {
  study::IntegrateOptions opts;
  opts.outDir = o.output;
  opts.integrands = study::splitList(o.integrands);
  opts.samplers = study::splitList(o.samplers);
  if (!o.ns.empty()) opts.ns = study::parseNList(o.ns);
  opts.instances = o.instances;
  opts.optimizedInstances = o.optimizedInstances;
  opts.optimizedMaxN = o.optimizedMaxN;
  opts.optEpochs = o.optEpochs;
  opts.optUnionWeight = o.optUnionWeight;
  if (!o.optObjective.empty()) opts.optObjective = parseObjective(o.optObjective);
  opts.neuralModels = o.neural;
  opts.assetRoot = resolveAssetRoot(o.assets);
  opts.envmaps = study::splitList(o.envmaps);
  opts.envmapsNamed = o.envmapsNamed;
  opts.seed = o.seed;
  opts.lobeChoice = o.lobeChoice;
  return opts;
}

// Runs the study with a progress bar, prints its RMSE table and notes, and
// plots it.
int runStudyIntegrate(const IntegrateCliOptions &o) {
  const study::IntegrateOptions opts = integrateOptions(o);
  const bool tty = ::isatty(STDERR_FILENO);
  // In a job of several ranks (mpirun, srun) rank 0 alone reports.
  const Ranks &ranks = Ranks::world();
  const bool quiet = o.quiet || !ranks.root();
  std::optional<ProgressBar> bar;
  bool barDrawn = false;
  study::IntegrateHooks hooks;
  hooks.message = [&](const std::string &text) {
    if (quiet) return;
    std::cerr << (barDrawn && tty ? "\n" : "") << "nuld: " << text << "\n";
  };
  hooks.progress = [&](long done, long total, const std::string &status) {
    if (!bar) bar.emplace("integrate", total, 0, quiet);
    bar->update(done, status);
    barDrawn = true;
  };
  const auto start = Clock::now();
  const study::IntegrateSummary summary = study::runIntegrateStudy(opts, hooks);
  const double seconds = secondsSince(start);
  if (!ranks.root()) return 0;
  if (bar)
    bar->finish(std::to_string(summary.rowsAdded) + " rows added, " +
                std::to_string(summary.rowsSkipped) + " already present");

  study::CsvTable table(study::integrateCsvPath(opts.outDir), study::integrateColumns());
  table.loadExisting();
  std::cout << study::rmseTable(table);
  for (const auto &note : summary.notes)
    if (note.rfind("note:", 0) == 0 || note.rfind("warning:", 0) == 0) std::cout << note << "\n";
  if (!o.quiet)
    std::cerr << "wrote " << table.path().string() << " (" << summary.rowsAdded
              << " new rows; optimized sets: " << summary.setsOptimized << " made, "
              << summary.setsFromCache << " from the cache) in " << formatDuration(seconds) << "\n";
  if (o.quiet) ::setenv("NULD_QUIET", "1", 1);  // plot_integrate.py stays silent too
  if (!o.noPlots)
    if (const auto warning = study::runIntegratePlots(opts.outDir))
      std::cerr << "nuld: warning: " << *warning << "\n";
  return 0;
}

}  // namespace

Runner addStudyIntegrate(CLI::App &app) {
  auto o = std::make_shared<IntegrateCliOptions>();
  app.add_option("-o,--output", o->output, "output directory (integrate.csv, plots, cache/)")
      ->required();
  app.add_option("--integrands", o->integrands,
                 "comma-separated: gaussian*step, quarterdisc*bilinear, envmap*cos, "
                 "disney*envmap, disney-grazing*envmap, disney-views*envmap (the lobe at 20 "
                 "and 70 degrees; these four once per map), disney*cosines (the lobe under a "
                 "smooth light, at 20, 45 and 70 degrees); or a full name such as "
                 "envmap:grace*cos (default: all)");
  app.add_option("--samplers", o->samplers,
                 "comma-separated backend words that serve the integration study: " +
                     backendSpellings(kIntegration) +
                     " (each as in renders: a classic word in its own mapping, the BRDF's "
                     "sample() on lobe integrands, and -tabulated through the tabulated lobe's "
                     "inverse CDF; optimized: sets optimized for each integrand's target; sot, "
                     "gbn: blue noise optimized for the target, sot-mapped, gbn-mapped: "
                     "optimized uniformly, then the inverse CDF, up to --optimized-max-n; "
                     "neural: a lobe family's sets shifted in the table's primary space, as "
                     "renders deal them, and its rows named +shift; +shift: any model's or "
                     "file's sets shifted so; nuld help backends) (default: every classic "
                     "word and its -tabulated, and optimized)")
      // The words only, before any reference is computed.
      ->check(parsedBy([](const std::string &text) {
        try {
          study::parseSamplers(study::splitList(text), {});
        } catch (const std::invalid_argument &e) {
          // The refusal names the option already; the check's prefix adds it again.
          const std::string what = e.what(), prefix = "--samplers: ";
          throw std::invalid_argument(what.starts_with(prefix) ? what.substr(prefix.size()) : what);
        }
      }));
  app.add_option("--n", o->ns, "comma-separated N (default 16,32,...,4096; any N >= 1)");
  app.add_option("--instances", o->instances,
                 "randomized instances per conventional sampler (default 128)")
      ->check(wholeNumberIn(1, 1 << 20));
  app.add_option("--optimized-instances", o->optimizedInstances,
                 "instances of optimized and neural sets (default 16)")
      ->check(wholeNumberIn(1, 1 << 20));
  app.add_option("--optimized-max-n", o->optimizedMaxN,
                 "largest N for optimized sets (default 1024): Algorithm 1's time grows with N "
                 "times the boxes, and its preset quadruples the boxes from N = 2048")
      ->check(wholeNumberIn(1, 1 << 20));
  app.add_option("--opt-objective", o->optObjective,
                 "objective of the direct optimization: soft (Algorithm 1, the preset's) or "
                 "l2asd (exact grid L2asd; 30-100x faster on the Disney lobe tables)")
      ->check(CLI::IsMember({toString(Objective::SoftBoxes), toString(Objective::ExactL2asd)}));
  app.add_option("--opt-union-weight", o->optUnionWeight,
                 "with --opt-objective l2asd: weight of the bank term (nuld optimize "
                 "--union-weight; default 3, as the render study's lobe banks; 0: instances "
                 "optimized apart)")
      ->check(nonNegativeNumber());
  app.add_option("--opt-epochs", o->optEpochs,
                 "epochs of the direct optimization (default: the target's preset: 1000 in 2D, "
                 "5000 on the sphere)")
      ->check(positiveNumber());
  app.add_option("--neural", o->neural, "trained model(s) (.nuldnet), each used at its own N")
      ->expected(1, -1);
  app.add_option("--assets", o->assets,
                 "asset root holding envmaps/ (default: $NULD_ASSETS, else ../shared/assets "
                 "beside the checkout)");
  app.add_option("--envmaps", o->envmaps,
                 "comma-separated maps for the sphere integrands: NAME (envmaps/NAME_latlong.exr "
                 "or .hdr, or NAME.exr/.hdr) or a path (default: grace; the supplement used "
                 "three Debevec maps, e.g. grace,galileo,beach; 'sun' is built in: the default "
                 "scene's sky with a sun 1e6 times brighter, the stability case)");
  app.add_option("--seed", o->seed, "seed of every randomization and of the optimization")
      ->capture_default_str()
      ->check(wholeNumber());
  addLobeChoiceOption(app, o->lobeChoice);
  app.add_flag("--no-plots", o->noPlots, "write only the CSV");
  app.add_flag("-q,--quiet", o->quiet, "no progress or notes on stderr (the table still prints)");
  return [o, &app] {
    // The maps serve the sphere integrands only (all of them by default).
    const std::vector<std::string> wanted = study::splitList(o->integrands);
    const bool maps = wanted.empty() || std::any_of(wanted.begin(), wanted.end(), [](auto &t) {
                        return t == "all" || t.find("envmap") != std::string::npos;
                      });
    onlyWhen(app, maps, {"--envmaps"}, "the environment-map integrands");
    checkAssets(app, o->assets, maps, "the environment-map integrands");
    o->envmapsNamed = app.count("--envmaps") > 0;
    return runStudyIntegrate(*o);
  };
}

}  // namespace nuld::cli
