#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

#include "sampler/io/atomic_file.h"
#include "sampler/io/round_trip.h"
#include "sampler/neural/neural_trainer.h"
#include "sampler/targets/target_spec.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"
#include "tools/nuld/progress.h"

namespace nuld::cli {

namespace {

// step, mean training loss since the previous row, held-out L2; rewritten
// whole (atomically) at every validation, so it always matches the run.
void writeValidationCurve(const std::string &path, const std::vector<Validation> &history) {
  std::ostringstream csv;
  csv.precision(9);
  csv << "step,mean_train_loss,validation_l2\n";
  for (const Validation &v : history) {
    csv << v.step << ',';
    if (std::isfinite(v.meanLoss)) csv << v.meanLoss;
    csv << ',' << v.l2 << '\n';
  }
  writeFileAtomically(path, csv.str());
}

}  // namespace

Runner addTrain(CLI::App &app) {
  struct Options {
    std::string target, output, mapping = "mapped", pullback = "balanced", arch = "supplement",
                                base = "rotated";
    NeuralSettings net;
    TrainerSettings train;
    long checkpointEvery = 0, stopAfter = -1;
    std::string keep = "best", sizes;
    bool resume = false, quiet = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("--target", o->target,
                 "target SPEC (z is the only input) or family:gaussian|bilinear|disney[:ARGS] "
                 "(gamma drawn per batch entry)")
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
  app.add_option("--hidden", o->net.hidden,
                 "hidden width (supplement: 64, 256, 512, 1024; default 256) or each point's "
                 "state width (graph; default 64)");
  app.add_option("--neighbours", o->net.neighbours, "graph: neighbours per point")
      ->capture_default_str();
  app.add_option("--rounds", o->net.rounds, "graph: message-passing rounds")->capture_default_str();
  app.add_option("--position-harmonics", o->net.positionHarmonics,
                 "graph: order of the torus harmonics that encode each point's position")
      ->capture_default_str();
  app.add_option("--stages", o->net.stages,
                 "graph: stages, each adding a residual computed from where the earlier ones "
                 "left the points (shared weights)")
      ->capture_default_str();
  app.add_option("--base", o->base,
                 "graph: how z randomizes the base set: rotated (the supplement's Cranley-"
                 "Patterson rotation of Sobol) or owen (Sobol Owen-scrambled by a hash of z; "
                 "see README)")
      ->check(oneOf(kBaseRandomizationNames))
      ->capture_default_str();
  app.add_flag("--discrepancy-gradient", o->net.discrepancyGradient,
               "graph: each point also sees the gradient of its set's grid L2 discrepancy at "
               "its current position (a learned descent step)");
  app.add_option("--sigma", o->net.sigma, "standard deviation of the Fourier frequencies")
      ->capture_default_str();
  app.add_option("--encoding-dims", o->net.encodingDims,
                 "width of the Fourier encoding of (z, gamma) (even; the supplement's is 32)")
      ->capture_default_str();
  app.add_option("--z-harmonics", o->net.zHarmonics,
                 "also encode z by every integer frequency up to this order (the torus's own "
                 "Fourier basis; not in the supplement; 0: off); needs a smaller --lr (see README)")
      ->capture_default_str();
  app.add_option("--offset-range", o->net.offsetRange,
                 "diagnostic: rotate the base set by R z, so offsets span [0, R)^2 (the "
                 "supplement's is 1); below 1 the sets are not randomized and are not for "
                 "rendering (see README)")
      ->check(CLI::Range(1e-9, 1.0))
      ->capture_default_str();
  app.add_option("--mapping", o->mapping,
                 "mapped (the net places u, the set is the target's inverse CDF of u) or "
                 "unmapped (the net places the points themselves)")
      ->check(CLI::IsMember({"mapped", "unmapped"}))
      ->capture_default_str();
  app.add_option("--gradient", o->pullback,
                 "mapped mode: exact (J^T g) or balanced (each coordinate's gradient divided by "
                 "how far x moves per unit of it, so stretched regions do not dominate)")
      ->check(oneOf(kGradientPullbackNames))
      ->capture_default_str();
  app.add_option("--steps", o->train.steps, "training steps")->capture_default_str();
  app.add_option("--batch", o->train.batch, "(z, gamma) pairs per step")->capture_default_str();
  app.add_option("--boxes", o->train.boxes, "boxes per set and step")->capture_default_str();
  app.add_option("--lr", o->train.lrStart, "initial learning rate")->capture_default_str();
  app.add_option("--lr-end", o->train.lrEnd, "final learning rate")->capture_default_str();
  app.add_option("--alpha", o->train.alphaStart, "initial sigmoid scale")->capture_default_str();
  app.add_option("--alpha-end", o->train.alphaEnd, "final sigmoid scale")->capture_default_str();
  app.add_option("--seed", o->net.seed, "seed of the weights, B, batches and boxes");
  app.add_option("--validation", o->train.validationSets,
                 "held-out (z, gamma) pairs scored by the grid L2 at every checkpoint (0: none)")
      ->capture_default_str();
  app.add_option("--validation-grid", o->train.validationGrid, "grid resolution of the held-out L2")
      ->capture_default_str();
  app.add_option("--keep", o->keep,
                 "which weights OUTPUT gets: best (the lowest held-out L2 seen, the untrained "
                 "net included) or last")
      ->check(CLI::IsMember({"best", "last"}))
      ->capture_default_str();
  app.add_option("--checkpoint-every", o->checkpointEvery,
                 "steps between checkpoints and validations (default: about every 5 %)");
  app.add_flag("--resume", o->resume, "continue from OUTPUT.ckpt if it exists");
  app.add_option("--stop-after", o->stopAfter, "stop (with a checkpoint) after this step");
  app.add_flag("-q,--quiet", o->quiet, "no progress bar or messages (results still print)");
  app.add_option("-o,--output", o->output, "model file to write")->required();
  return [o, &app] {
    NeuralSettings ns = o->net;
    ns.arch = parseNetworkArch(o->arch);
    ns.base = parseBaseRandomization(o->base);
    if (ns.arch == NetworkArch::Graph && app.count("--hidden") == 0) ns.hidden = 64;
    if (ns.arch == NetworkArch::Supplement)
      for (const char *graphOnly : {"--neighbours", "--rounds", "--position-harmonics", "--stages",
                                    "--discrepancy-gradient", "--base"})
        if (app.count(graphOnly))
          throw std::invalid_argument(std::string(graphOnly) + " applies to --arch graph only");
    ns.trainingNs = parseSizeList("--n", o->sizes);
    ns.n = ns.trainingNs.front();
    if (ns.trainingNs.size() == 1)
      ns.trainingNs.clear();  // one size: the file records n alone, as before
    else if (ns.arch != NetworkArch::Graph)
      throw std::invalid_argument("--n " + o->sizes +
                                  ": several sizes need --arch graph (the supplement's network "
                                  "emits a fixed N)");
    ns.family = o->target;
    ns.mapped = o->mapping == "mapped";
    TrainerSettings ts = o->train;
    ts.seed = ns.seed;
    ts.pullback = parseGradientPullback(o->pullback);
    NeuralGenerator gen(ns);
    NeuralTrainer trainer(gen, ts);

    const std::string ckpt = o->output + ".ckpt";
    if (o->resume && std::filesystem::exists(ckpt)) {
      trainer.loadCheckpoint(ckpt);
      std::cerr << "resuming from " << ckpt << " at step " << trainer.step() << "\n";
    } else if (o->resume) {
      std::cerr << "no checkpoint at " << ckpt << "; starting fresh\n";
    }
    if (!o->quiet)
      std::cerr << "train " << gen.family().spec() << ": arch=" << toString(ns.arch)
                << " n=" << gen.metadata().at("n")
                << (ns.trainingNs.empty() ? "" : " training_n=" + gen.metadata().at("training_n"))
                << " hidden=" << ns.hidden << " parameters=" << gen.parameterCount() << " "
                << ts.describe() << "\n";
    const long every = o->checkpointEvery > 0 ? o->checkpointEvery : std::max(1, ts.steps / 20);
    const int until = o->stopAfter >= 0 ? int(std::min<long>(o->stopAfter, ts.steps)) : ts.steps;
    const bool validating = ts.validationSets > 0;
    const std::string bestPath = o->output + ".best", curvePath = o->output + ".validation.csv";
    std::string heldOut;  // the progress bar's validation part
    // Scores the current weights; a new best is written to OUTPUT.best before
    // the checkpoint that records it, so a resumed run never lacks its file.
    const auto validate = [&] {
      const Validation v = trainer.validate();
      const Validation best = *trainer.best();
      if (best.step == v.step)
        gen.save(bestPath, {{"train_settings", ts.describe()},
                            {"train_steps", std::to_string(v.step)},
                            {"validation_l2", formatRoundTrip(v.l2)}});
      writeValidationCurve(curvePath, trainer.history());
      heldOut = "  held-out L2 " + shortNumber(v.l2) + " (best " + shortNumber(best.l2) + " @" +
                std::to_string(best.step) + ")";
    };
    if (validating && trainer.history().empty()) validate();  // the untrained net's score
    ProgressBar bar("step", ts.steps, trainer.step(), o->quiet);
    TrainReport last;
    while (trainer.step() < until) {
      const int next = int(std::min<long>(until, (trainer.step() / every + 1) * every));
      trainer.run(next, [&](const TrainReport &r) {
        last = r;
        bar.update(r.step, "loss " + shortNumber(r.loss) + "  lr " + shortNumber(r.lr) +
                               "  alpha " + shortNumber(r.alpha) + heldOut);
      });
      if (validating) validate();
      if (trainer.step() < ts.steps) trainer.saveCheckpoint(ckpt);
    }
    if (trainer.step() < ts.steps) {
      std::cerr << "\nstopped after step " << trainer.step() << "; checkpoint in " << ckpt
                << " (continue with --resume)\n";
      return 0;
    }
    bar.finish("loss " + shortNumber(last.loss) + heldOut);
    const bool keepBest = validating && o->keep == "best";
    if (keepBest) {
      std::filesystem::rename(bestPath, o->output);
    } else {
      std::map<std::string, std::string> extra = {{"train_settings", ts.describe()},
                                                  {"train_steps", std::to_string(trainer.step())}};
      if (validating) extra["validation_l2"] = formatRoundTrip(trainer.history().back().l2);
      gen.save(o->output, extra);
      std::filesystem::remove(bestPath);
    }
    std::filesystem::remove(ckpt);
    // The split the neural issue asks for (this session's steps only).
    std::printf("final_loss %.6g\nmlp_seconds %.3f\nloss_kernel_seconds %.3f\n", last.loss,
                last.mlpSeconds, last.lossSeconds);
    if (validating) {
      const Validation best = *trainer.best();
      std::printf("validation_l2_first %.6g\nvalidation_l2_last %.6g\n",
                  trainer.history().front().l2, trainer.history().back().l2);
      std::printf("validation_l2_best %.6g\nbest_step %d\nkept %s\n", best.l2, best.step,
                  keepBest ? "best" : "last");
    }
    if (!o->quiet)
      std::cerr << "wrote model " << o->output
                << (keepBest ? " (the best held-out weights, step " +
                                   std::to_string(trainer.best()->step) + ")"
                             : std::string())
                << (validating ? "; held-out curve in " + curvePath : std::string()) << "\n";
    return 0;
  };
}

}  // namespace nuld::cli
