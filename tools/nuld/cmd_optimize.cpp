#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "backends/ranks.h"
#include "sampler/io/atomic_file.h"
#include "sampler/io/pointset_io.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/io/round_trip.h"
#include "sampler/metrics/discrepancy.h"
#include "sampler/optimize/optimizer.h"
#include "sampler/resources.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/target_spec.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"
#include "tools/nuld/interrupt_note.h"
#include "tools/nuld/progress.h"

namespace nuld::cli {

namespace {

struct OptimizeOptions {
  std::string target, preset, mass, mapping, objective, boxKind, output;
  std::size_t n = 0, instances = 1;
  long epochs = -1, boxes = -1;
  // Unset: the preset's value (no sentinel a user could type by accident).
  std::optional<double> lr, lrEnd, alpha, alphaEnd, ramp;
  std::optional<double> unionWeight;  // nullopt: the preset's
  long unionGroup = 0;
  std::string nested;
  double nestedPower = 1;
  std::uint64_t seed = kDefaultSeed;
  RunFlags run;
};

// --mass: exact (0 space samples) or mc:K (K > 0).
std::size_t parseMass(const std::string &text) {
  if (text == "exact") return 0;
  if (text.rfind("mc:", 0) != 0)
    throw std::invalid_argument("'" + text + "': expected exact or mc:K");
  std::size_t k = 0;
  try {
    k = std::stoul(text.substr(3));
  } catch (...) {
  }
  if (k == 0)
    throw std::invalid_argument("'" + text + "': expected mc:K with K a positive integer");
  return k;
}

// The preset for the target, with the options' overrides; throws naming an
// option that does not parse.
OptimizerSettings settingsFrom(const OptimizeOptions &o, const Target &target) {
  OptimizerSettings s = presetSettings(o.preset.empty() ? defaultPreset(target) : o.preset, o.n);
  s.instances = o.instances;
  s.seed = o.seed;
  if (o.epochs > 0) s.epochs = int(o.epochs);
  if (o.boxes > 0) s.boxes = std::size_t(o.boxes);
  if (!o.boxKind.empty()) s.boxKind = parseBoxKind(o.boxKind);
  if (!o.mapping.empty()) s.mapping = parseMapping(o.mapping);
  if (!o.objective.empty()) s.objective = parseObjective(o.objective);
  // The periodic objective's points live on the torus.
  if (s.objective == Objective::PeriodicL2 && o.mapping.empty()) s.mapping = Mapping::Toroidal;
  if (!o.mass.empty()) s.mcSamples = parseMass(o.mass);
  if (o.lr) s.lrStart = *o.lr;
  if (o.lrEnd) s.lrEnd = *o.lrEnd;
  if (o.alpha) s.alphaStart = *o.alpha;
  if (o.alphaEnd) s.alphaEnd = *o.alphaEnd;
  if (o.ramp) s.rampFraction = *o.ramp;
  // A preset's bank term (sphere-exact's) needs two instances to couple.
  if (o.unionWeight)
    s.unionWeight = *o.unionWeight;
  else if (s.instances < 2)
    s.unionWeight = 0;
  s.unionGroup = std::size_t(o.unionGroup);
  if (!o.nested.empty()) {
    const std::vector<std::size_t> sizes = parseSizeList("--nested", o.nested);
    // One size: the chain M, 2M, 4M ... below N; several: those prefixes.
    s.nestedSizes = sizes.size() == 1 ? nestedChain(sizes[0], s.n) : sizes;
    std::sort(s.nestedSizes.begin(), s.nestedSizes.end());
    if (s.nestedSizes.empty() || s.nestedSizes.back() >= s.n)
      throw std::invalid_argument("--nested '" + o.nested + "': prefix sizes must be below --n " +
                                  std::to_string(s.n));
  }
  s.nestedPower = o.nestedPower;
  return s;
}

// The mean L2asd and D* of the set's instances (against the target unless it
// is uniform), recorded with the points and printed.
std::pair<double, double> finalMetrics(const PointSet &set, const Target &target) {
  const bool uniform = target.isUniform();
  double l2 = 0, dstar = 0;
  for (std::size_t k = 0; k < set.instances(); ++k) {
    l2 += (uniform ? l2asd(set.instance(k)) : nonuniformL2asd(set.instance(k), target)) /
          double(set.instances());
    dstar +=
        starDiscrepancy(set.instance(k), uniform ? nullptr : &target) / double(set.instances());
  }
  return {l2, dstar};
}

// The mean over the instances of the L2 discrepancy the objective lowers:
// the periodic L2 for l2per, else the L2asd (against the target unless it is
// uniform).
double objectiveL2(const PointSet &set, const Target &target, Objective objective) {
  double sum = 0;
  for (std::size_t k = 0; k < set.instances(); ++k)
    sum += objective == Objective::PeriodicL2 ? periodicL2(set.instance(k))
           : target.isUniform()               ? l2asd(set.instance(k))
                                              : nonuniformL2asd(set.instance(k), target);
  return sum / double(set.instances());
}

// Sizes beyond which the final L2 and D* (O(N^2) each) are left to
// `nuld eval`: about a minute of the metrics on two cores.
constexpr double kMaxMetricPairs = 2e10;

// Up front, before anything is allocated: a size the machine cannot hold is
// refused, and so is a run whose first epoch (the widest sigmoid, the
// slowest) would take over an hour before the progress bar first moves; a
// first epoch over half a minute is announced. The constants are the
// measured costs (tools/experiments/optimizer_run_estimates.md:
// state per point, seconds per box-point pair of an epoch at alpha 20, per
// pair of points for the exact objectives, falling roughly as alpha^-1/2
// and faster above), rounded up so that the check errs on refusing.
void checkResources(const OptimizerSettings &s, bool quiet) {
  constexpr double kBytesPerPoint = 160, kSecondsPerPair = 2e-9, kMaxFirstEpochSeconds = 3600;
  const double points = double(s.n) * double(s.instances);
  requireMemory(points * kBytesPerPoint, "optimize: " + std::to_string(s.instances) + " x " +
                                             std::to_string(s.n) + " points");
  const bool soft = s.objective == Objective::SoftBoxes;
  const double pairs = soft ? points * double(s.boxes) : points * double(s.n);
  const double seconds =
      pairs * kSecondsPerPair * (soft ? std::min(1.0, std::sqrt(20 / s.alphaStart)) : 1.0);
  const std::string what = formatShort(pairs) + (soft ? " box-point pairs" : " point pairs");
  if (seconds > kMaxFirstEpochSeconds)
    throw std::invalid_argument("optimize: the first epoch alone compares about " + what +
                                ", about " + formatShort(seconds / 3600) +
                                " hours here before the progress bar first moves (" +
                                std::to_string(s.epochs) +
                                " epochs in all); use fewer points or instances, or fewer --boxes");
  if (!quiet && seconds > 30)
    std::cerr << "optimize: the first epoch compares about " << what << ", about "
              << formatDuration(seconds) << " here; later epochs are faster\n";
}

// A learning rate far too large leaves the points scattered to the
// domain's edges with a finite loss: the sets then end far worse than the
// Owen-Sobol sets they started from. Refuse to write them.
void refuseDiverged(const DirectOptimizer &opt, const PointSet &set, const Target &target,
                    const OptimizerSettings &s, const std::string &ckpt) {
  const double startL2 = objectiveL2(opt.points(opt.initialState()), target, s.objective);
  const double endL2 = objectiveL2(set, target, s.objective);
  if (endL2 <= 2 * startL2) return;
  std::filesystem::remove(ckpt);  // the state of a diverged run is no use to resume
  throw std::runtime_error(
      "optimize: the sets ended with L2 discrepancy " + formatRoundTrip(endL2) +
      ", more than twice the " + formatRoundTrip(startL2) +
      " of the Owen-Sobol sets they started from: the optimization diverged; lower --lr "
      "(it ran from " +
      formatRoundTrip(s.lrStart) + " to " + formatRoundTrip(s.lrEnd) + "); nothing was written");
}

// Writes the sets of the final `state` (after the divergence check) and
// prints their metrics.
void writeOptimized(const OptimizeOptions &o, const DirectOptimizer &opt, const Target &target,
                    const OptimizerSettings &s, const OptimizerState &state,
                    const std::string &ckpt) {
  PointSet set = opt.points(state);
  // Above kMaxMetricPairs the final metrics, and with them the divergence
  // check that needs the L2, are left to `nuld eval`: divergence then shows
  // only as a non-finite loss, which stops the run.
  const double metricPairs = double(s.n) * double(s.n) * double(s.instances);
  std::optional<std::pair<double, double>> metrics;
  if (metricPairs <= kMaxMetricPairs) {
    refuseDiverged(opt, set, target, s, ckpt);
    metrics = finalMetrics(set, target);
    std::ostringstream m;
    m.precision(9);
    m << "l2asd=" << metrics->first << " dstar=" << metrics->second;
    setMeta(set, meta::kFinalMetrics, m.str());
  }
  writePointSet(o.output, set);
  if (metrics)
    std::printf("l2asd %.9g\ndstar %.9g\n", metrics->first, metrics->second);
  else
    std::cerr << "note: the final l2asd and dstar (O(N^2): " << formatShort(metricPairs)
              << " point pairs) are left to `nuld eval " << o.output << "`\n";
  if (!o.run.quiet)
    std::cerr << "wrote " << set.instances() << " x " << set.n << " points to " << o.output << "\n";
}

// This rank's part of the instances: all of them in a single process, a
// contiguous share in a job of several ranks (backends/ranks.h), which
// each rank optimizes and checkpoints on its own.
struct InstancePart {
  std::size_t first = 0, count = 0;
  std::string checkpoint;
};

InstancePart instancePart(const std::string &output, const OptimizerSettings &s,
                          const Ranks &ranks) {
  if (!ranks.distributed()) return {0, s.instances, output + ".ckpt"};
  if (s.unionWeight > 0)
    throw std::invalid_argument(
        "--union-weight: the bank term couples all instances, so they cannot be split over " +
        std::to_string(ranks.size()) + " ranks; run this command as one process (no mpirun)");
  const std::size_t K = std::size_t(ranks.size()), r = std::size_t(ranks.rank());
  const std::size_t first = s.instances * r / K, end = s.instances * (r + 1) / K;
  return {first, end - first,
          output + ".ckpt.instances-" + std::to_string(first) + "-" + std::to_string(end)};
}

int runOptimize(const OptimizeOptions &o, const Target &target, const OptimizerSettings &s) {
  const Ranks &ranks = Ranks::world();
  if (ranks.root()) checkDestination(o.output);
  checkResources(s, o.run.quiet || !ranks.root());
  const DirectOptimizer opt(target, s);
  const InstancePart part = instancePart(o.output, s, ranks);

  // In a job, rank 0 shows its own part's progress: every part runs the
  // same epochs.
  const bool quiet = o.run.quiet || !ranks.root();
  RunFlags flags = o.run;
  flags.quiet = quiet;
  std::ostream *log = quiet ? nullptr : &std::cerr;
  std::vector<Point2> params;  // this part's, at the end
  if (part.count > 0) {
    OptimizerSettings partSettings = s;
    partSettings.instances = part.count;
    partSettings.firstInstance = part.first;
    const DirectOptimizer partOpt(target, partSettings);
    OptimizerState state = partOpt.initialState();
    std::optional<ProgressBar> bar;
    EpochReport last;
    const ResumableRun run = resumableRun(partOpt, target.spec(), state, [&](const EpochReport &r) {
      last = r;
      std::string status = "loss " + formatShort(r.loss);
      if (s.unionWeight > 0) status += "  union " + formatShort(r.unionLoss);
      if (s.objective == Objective::SoftBoxes) status += "  alpha " + formatShort(r.alpha);
      bar->update(r.epoch, status + "  lr " + formatShort(r.lr));
    });
    const InterruptNote interruptNote(part.checkpoint);
    resumeRun(run, part.checkpoint, flags, log);
    if (!quiet) {
      std::cerr << "optimize " << target.spec() << ": " << s.describe() << "\n";
      if (ranks.distributed())
        std::cerr << "optimize: instances split over " << ranks.size()
                  << " ranks; the bar follows rank 0's " << part.count << " of " << s.instances
                  << "\n";
    }
    bar.emplace("epoch", s.epochs, state.epoch, quiet);
    // Every part runs the same epochs, so every rank stops or completes alike.
    if (!driveRun(run, part.checkpoint, flags, log)) return 0;
    bar->finish("loss " + formatShort(last.loss));
    params = std::move(state.params);
  }

  // Rank 0 joins the parts in instance order: the state one process ends in.
  const std::vector<std::string> parts = ranks.gather(ByteWriter().put(params).take());
  if (ranks.root()) {
    OptimizerState state;
    state.epoch = s.epochs;
    for (const std::string &bytes : parts) {
      const auto part = fromBytes<std::vector<Point2>>(bytes);
      state.params.insert(state.params.end(), part.begin(), part.end());
    }
    writeOptimized(o, opt, target, s, state, part.checkpoint);
  }
  // The checkpoints go once the sets are written.
  ranks.barrier();
  std::filesystem::remove(part.checkpoint);
  return 0;
}

}  // namespace

Runner addOptimize(CLI::App &app) {
  auto o = std::make_shared<OptimizeOptions>();
  app.add_option("--target", o->target, targetOptionHelp("target SPEC"))
      ->required()
      ->check(targetFamily());
  app.add_option("--n", o->n, "points per set")->required()->check(positiveNumber());
  app.add_option(
         "--preset", o->preset,
         "uniform, nonuniform, nonuniform-mc, sphere, sphere-mc or sphere-exact (default: by "
         "target)")
      ->check(parsedBy([](const std::string &name) { presetSettings(name, 1); }));
  app.add_option("--epochs", o->epochs, "override the preset's epochs")->check(positiveNumber());
  app.add_option("--boxes", o->boxes, "boxes per epoch")->check(positiveNumber());
  app.add_option("--box-kind", o->boxKind, kBoxKindNames.expected())->check(oneOf(kBoxKindNames));
  app.add_option("--mass", o->mass, "exact or mc:K (Monte Carlo with K space samples)")
      ->check(parsedBy(parseMass));
  app.add_option("--mapping", o->mapping, kMappingNames.expected())->check(oneOf(kMappingNames));
  app.add_option("--objective", o->objective,
                 "soft (Algorithm 1), l2asd (exact closed form; uniform and grid targets) or "
                 "l2per (periodic L2, closed form; uniform target, toroidal: sets that keep "
                 "their quality under any Cranley-Patterson shift)")
      ->check(oneOf(kObjectiveNames));
  app.add_option("--lr", o->lr, "initial learning rate");
  app.add_option("--lr-end", o->lrEnd, "final learning rate");
  app.add_option("--alpha", o->alpha, "initial sigmoid scale");
  app.add_option("--alpha-end", o->alphaEnd, "final sigmoid scale");
  app.add_option("--ramp", o->ramp, "fraction of the epochs over which alpha rises");
  app.add_option("--instances", o->instances, "sets optimized together")->check(positiveNumber());
  app.add_option("--union-weight", o->unionWeight,
                 "bank term (l2asd, >= 2 instances): weight of the L2asd of the union of each "
                 "group of instances, which keeps a bank's sets complementary on peaked targets "
                 "(default 0: off)")
      ->check(nonNegativeNumber());
  app.add_option("--union-group", o->unionGroup,
                 "instances per group of the bank term, regrouped every epoch (default: "
                 "about 256 points, at least 2 instances)")
      ->check(wholeNumberIn(2, 1 << 20));
  app.add_option("--nested", o->nested,
                 "nested sets: also optimize each instance's first M points as a set, for M = "
                 "the given size, twice it, ... below --n (one size), or for the listed sizes "
                 "(M1,M2,...), so that one file serves renders at any spp up to N by prefixes "
                 "(default: off)")
      ->check(parsedBy([](const std::string &text) { parseSizeList("sizes", text); }));
  app.add_option("--nested-power", o->nestedPower,
                 "weight (M / N)^power of a prefix's loss beside the full set's (default 1)")
      ->check(nonNegativeNumber());
  app.add_option("--seed", o->seed, "seed of the Sobol start and of the boxes")
      ->capture_default_str()
      ->check(wholeNumber());
  addRunFlags(app, o->run, "epoch");
  app.add_option("-o,--output", o->output, "point-set file to write")->required();
  return [o, &app] {
    const auto target = makeTarget(o->target);
    const OptimizerSettings s = settingsFrom(*o, *target);
    // The exact objectives have no boxes, no masses and no sigmoid.
    onlyWhen(app, s.objective == Objective::SoftBoxes,
             {"--boxes", "--box-kind", "--mass", "--alpha", "--alpha-end", "--ramp"},
             app.count("--objective") ? std::string("--objective soft")
                                      : "--objective soft (the preset for this target uses " +
                                            toString(s.objective) + ")");
    onlyWhen(app, s.unionWeight > 0, {"--union-group"}, "--union-weight > 0");
    onlyWhen(app, !s.nestedSizes.empty(), {"--nested-power"}, "--nested M");
    return runOptimize(*o, *target, s);
  };
}

}  // namespace nuld::cli
