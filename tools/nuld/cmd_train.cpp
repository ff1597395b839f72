#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "sampler/io/round_trip.h"
#include "sampler/neural/neural_trainer.h"
#include "sampler/targets/target_spec.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"
#include "tools/nuld/interrupt_note.h"
#include "tools/nuld/progress.h"

namespace nuld::cli {

namespace {

struct TrainOptions {
  std::string target, output, mapping = "mapped", pullback = "balanced", arch = "supplement",
                              base = "rotated";
  NeuralSettings net;
  TrainerSettings train;
  std::string keep = "best", sizes;
  RunFlags run;
};

// The network's options: architecture, widths, encodings, the graph's parts.
void addNetworkOptions(CLI::App &app, TrainOptions &o) {
  app.add_option("--hidden", o.net.hidden,
                 "hidden width (supplement: 64, 256, 512, 1024; default 256) or each point's "
                 "state width (graph; default 64)");
  app.add_option("--neighbours", o.net.neighbours, "graph: neighbours per point")
      ->capture_default_str();
  app.add_option("--rounds", o.net.rounds, "graph: message-passing rounds")->capture_default_str();
  app.add_option("--position-harmonics", o.net.positionHarmonics,
                 "graph: order of the torus harmonics that encode each point's position")
      ->capture_default_str();
  app.add_option("--stages", o.net.stages,
                 "graph: stages, each adding a residual computed from where the earlier ones "
                 "left the points (shared weights)")
      ->capture_default_str();
  app.add_option("--base", o.base,
                 "graph: how z randomizes the base set: rotated (the supplement's Cranley-"
                 "Patterson rotation of Sobol) or owen (Sobol Owen-scrambled by a hash of z; "
                 "see README)")
      ->check(oneOf(kBaseRandomizationNames))
      ->capture_default_str();
  app.add_flag("--discrepancy-gradient", o.net.discrepancyGradient,
               "graph: each point also sees the gradient of its set's grid L2 discrepancy at "
               "its current position (a learned descent step)");
  app.add_flag("--train-shifted", o.train.shiftedSets,
               "mapped lobe families: train and validate the sets Cranley-Patterson shifted in "
               "the table's primary space, as the renderer deals them out (see README)");
  app.add_flag("--centred", o.net.centred,
               "graph: each stage's residuals lose their mean over the set, so no set moves as "
               "a whole (see README)");
  app.add_option("--sigma", o.net.sigma, "standard deviation of the Fourier frequencies")
      ->capture_default_str();
  app.add_option("--encoding-dims", o.net.encodingDims,
                 "width of the Fourier encoding of (z, gamma) (even; the supplement's is 32)")
      ->capture_default_str();
  app.add_option("--z-harmonics", o.net.zHarmonics,
                 "also encode z by every integer frequency up to this order (the torus's own "
                 "Fourier basis; not in the supplement; 0: off); needs a smaller --lr (see README)")
      ->capture_default_str();
  app.add_option("--offset-range", o.net.offsetRange,
                 "diagnostic: rotate the base set by R z, so offsets span [0, R)^2 (the "
                 "supplement's is 1); below 1 the sets are not randomized and are not for "
                 "rendering (see README)")
      ->check(numberIn(1e-9, 1.0))
      ->capture_default_str();
  app.add_option("--mapping", o.mapping,
                 "mapped (the net places u, the set is the target's inverse CDF of u) or "
                 "unmapped (the net places the points themselves)")
      ->check(CLI::IsMember({"mapped", "unmapped"}))
      ->capture_default_str();
  app.add_option("--gradient", o.pullback,
                 "mapped mode: exact (J^T g) or balanced (each coordinate's gradient divided by "
                 "how far x moves per unit of it, so stretched regions do not dominate)")
      ->check(oneOf(kGradientPullbackNames))
      ->capture_default_str();
}

// The training run's options: steps, batch, schedules, validation, keep.
void addTrainingOptions(CLI::App &app, TrainOptions &o) {
  app.add_option("--steps", o.train.steps, "training steps")->capture_default_str();
  app.add_option("--batch", o.train.batch, "(z, gamma) pairs per step")
      ->capture_default_str()
      ->check(wholeNumberIn(1, 1 << 16));
  app.add_option("--boxes", o.train.boxes, "boxes per set and step")
      ->capture_default_str()
      ->check(wholeNumberIn(1, 1 << 24));
  app.add_option("--lr", o.train.lrStart, "initial learning rate")->capture_default_str();
  app.add_option("--lr-end", o.train.lrEnd, "final learning rate")->capture_default_str();
  app.add_option("--alpha", o.train.alphaStart, "initial sigmoid scale")->capture_default_str();
  app.add_option("--alpha-end", o.train.alphaEnd, "final sigmoid scale")->capture_default_str();
  o.net.seed = kDefaultSeed;  // the commands' one default (sampler/sequences/rng.h)
  app.add_option("--seed", o.net.seed, "seed of the weights, B, batches and boxes")
      ->capture_default_str()
      ->check(wholeNumber());
  app.add_option("--validation", o.train.validationSets,
                 "held-out (z, gamma) pairs scored by the grid L2 at every checkpoint (0: none)")
      ->capture_default_str()
      ->check(wholeNumberIn(0, 1 << 16));
  app.add_option("--validation-grid", o.train.validationGrid, "grid resolution of the held-out L2")
      ->capture_default_str()
      ->check(wholeNumberIn(8, 4096));
  app.add_option("--keep", o.keep,
                 "which weights OUTPUT gets: best (the lowest held-out L2 seen, the untrained "
                 "net included) or last")
      ->check(CLI::IsMember({"best", "last"}))
      ->capture_default_str();
  addRunFlags(app, o.run, "step", " and validations");
  app.add_option("-o,--output", o.output, "model file to write")->required();
}

// The generator and trainer settings the options stand for; throws naming
// the option that does not apply or does not parse.
std::pair<NeuralSettings, TrainerSettings> settingsFrom(const TrainOptions &o,
                                                        const CLI::App &app) {
  NeuralSettings ns = o.net;
  ns.arch = parseNetworkArch(o.arch);
  ns.base = parseBaseRandomization(o.base);
  if (ns.arch == NetworkArch::Graph && app.count("--hidden") == 0) ns.hidden = 64;
  onlyWhen(app, ns.arch == NetworkArch::Graph,
           {"--neighbours", "--rounds", "--position-harmonics", "--stages",
            "--discrepancy-gradient", "--centred", "--base"},
           "--arch graph");
  ns.trainingNs = parseSizeList("--n", o.sizes);
  ns.n = ns.trainingNs.front();
  if (ns.trainingNs.size() == 1)
    ns.trainingNs.clear();  // one size: the file records n alone, as before
  else if (ns.arch != NetworkArch::Graph)
    throw std::invalid_argument("--n " + o.sizes +
                                ": several sizes need --arch graph (the supplement's network "
                                "emits a fixed N)");
  ns.family = o.target;
  ns.mapped = o.mapping == "mapped";
  TrainerSettings ts = o.train;
  if (ts.shiftedSets && !ns.mapped)
    throw std::invalid_argument(
        "--train-shifted: shifts happen in the target's primary space, so the sets must be mapped "
        "(drop --mapping unmapped)");
  ts.seed = ns.seed;
  ts.pullback = parseGradientPullback(o.pullback);
  return {ns, ts};
}

int runTrain(const TrainOptions &o, const NeuralSettings &ns, const TrainerSettings &ts) {
  NeuralGenerator gen(ns);
  const auto trainer = NeuralTrainer::make(gen, ts);

  const std::string ckpt = o.output + ".ckpt";
  const bool quiet = o.run.quiet, validating = ts.validationSets > 0;
  // The progress bar's validation part: the latest held-out L2 and the best.
  const auto heldOut = [&trainer] {
    if (trainer->history().empty()) return std::string();
    const Validation best = *trainer->best();
    return "  held-out L2 " + formatShort(trainer->history().back().l2) + " (best " +
           formatShort(best.l2) + " @" + std::to_string(best.step) + ")";
  };
  std::optional<ProgressBar> bar;
  TrainReport last;
  const ResumableRun run = trainer->resumableRun(o.output, [&](const TrainReport &r) {
    last = r;
    bar->update(r.step, "loss " + formatShort(r.loss) + "  lr " + formatShort(r.lr) + "  alpha " +
                            formatShort(r.alpha) + heldOut());
  });
  const InterruptNote interruptNote(ckpt);
  resumeRun(run, ckpt, o.run, &std::cerr);
  if (!quiet)
    std::cerr << "train " << gen.family().spec() << ": arch=" << toString(ns.arch)
              << " n=" << gen.metadata().at("n")
              << (ns.trainingNs.empty() ? "" : " training_n=" + gen.metadata().at("training_n"))
              << " hidden=" << ns.hidden << " parameters=" << gen.parameterCount() << " "
              << ts.describe() << "\n";
  bar.emplace("step", ts.steps, trainer->step(), quiet);
  if (!driveRun(run, ckpt, o.run, &std::cerr)) return 0;
  bar->finish("loss " + formatShort(last.loss) + heldOut());
  const bool keptBest = trainer->writeModel(o.output, o.keep == "best");
  std::filesystem::remove(ckpt);
  // The split the neural issue asks for (this session's steps only).
  std::printf("final_loss %.6g\nmlp_seconds %.3f\nloss_kernel_seconds %.3f\n", last.loss,
              last.mlpSeconds, last.lossSeconds);
  if (validating) {
    const Validation best = *trainer->best();
    std::printf("validation_l2_first %.6g\nvalidation_l2_last %.6g\n",
                trainer->history().front().l2, trainer->history().back().l2);
    std::printf("validation_l2_best %.6g\nbest_step %d\nkept %s\n", best.l2, best.step,
                keptBest ? "best" : "last");
  }
  if (!quiet)
    std::cerr << "wrote model " << o.output
              << (keptBest ? " (the best held-out weights, step " +
                                 std::to_string(trainer->best()->step) + ")"
                           : std::string())
              << (validating ? "; held-out curve in " + NeuralTrainer::validationCurvePath(o.output)
                             : std::string())
              << "\n";
  return 0;
}

}  // namespace

Runner addTrain(CLI::App &app) {
  auto o = std::make_shared<TrainOptions>();
  app.add_option("--target", o->target,
                 targetOptionHelp("target SPEC (z is the only input) or a family "
                                  "family:gaussian|bilinear|disney[:ARGS] (gamma drawn per "
                                  "batch entry); targets"))
      ->required();
  app.add_option("--n", o->sizes,
                 "points per set; graph: several sizes as N1,N2,... (one per step in turn; the "
                 "first is the model's default)")
      ->required();
  app.add_option("--arch", o->arch,
                 "supplement (the paper's MLP of z and gamma) or graph (ours: per-point message "
                 "passing over the base set's nearest neighbours; see README)")
      ->check(oneOf(kNetworkArchNames))
      ->capture_default_str();
  addNetworkOptions(app, *o);
  addTrainingOptions(app, *o);
  return [o, &app] {
    const auto [ns, ts] = settingsFrom(*o, app);
    return runTrain(*o, ns, ts);
  };
}

}  // namespace nuld::cli
