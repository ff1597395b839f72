#include <cstdio>
#include <filesystem>
#include <iostream>

#include "sampler/neural/neural_trainer.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"
#include "tools/nuld/progress.h"

namespace nuld::cli {

Runner addTrain(CLI::App &app) {
  struct Options {
    std::string target, output, mapping = "mapped";
    NeuralSettings net;
    TrainerSettings train;
    long checkpointEvery = 0, stopAfter = -1;
    bool resume = false, quiet = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("--target", o->target,
                 "target SPEC (z is the only input) or family:gaussian|bilinear|disney[:ARGS] "
                 "(gamma drawn per batch entry)")
      ->required();
  app.add_option("--n", o->net.n, "points per set")->required()->check(CLI::PositiveNumber);
  app.add_option("--hidden", o->net.hidden, "hidden layer width (64, 256, 512, 1024)")
      ->capture_default_str();
  app.add_option("--sigma", o->net.sigma, "standard deviation of the Fourier frequencies")
      ->capture_default_str();
  app.add_option("--mapping", o->mapping,
                 "mapped (the net places u, the set is the target's inverse CDF of u) or "
                 "unmapped (the net places the points themselves)")
      ->check(CLI::IsMember({"mapped", "unmapped"}))
      ->capture_default_str();
  app.add_option("--steps", o->train.steps, "training steps")->capture_default_str();
  app.add_option("--batch", o->train.batch, "(z, gamma) pairs per step")->capture_default_str();
  app.add_option("--boxes", o->train.boxes, "boxes per set and step")->capture_default_str();
  app.add_option("--lr", o->train.lrStart, "initial learning rate")->capture_default_str();
  app.add_option("--lr-end", o->train.lrEnd, "final learning rate")->capture_default_str();
  app.add_option("--alpha", o->train.alphaStart, "initial sigmoid scale")->capture_default_str();
  app.add_option("--alpha-end", o->train.alphaEnd, "final sigmoid scale")->capture_default_str();
  app.add_option("--seed", o->net.seed, "seed of the weights, B, batches and boxes");
  app.add_option("--checkpoint-every", o->checkpointEvery,
                 "steps between checkpoints (default: about every 5 %)");
  app.add_flag("--resume", o->resume, "continue from OUTPUT.ckpt if it exists");
  app.add_option("--stop-after", o->stopAfter, "stop (with a checkpoint) after this step");
  app.add_flag("-q,--quiet", o->quiet, "no progress bar or messages (results still print)");
  app.add_option("-o,--output", o->output, "model file to write")->required();
  return [o] {
    NeuralSettings ns = o->net;
    ns.family = o->target;
    ns.mapped = o->mapping == "mapped";
    TrainerSettings ts = o->train;
    ts.seed = ns.seed;
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
      std::cerr << "train " << gen.family().spec() << ": n=" << ns.n << " hidden=" << ns.hidden
                << " parameters=" << gen.parameterCount() << " " << ts.describe() << "\n";
    const long every = o->checkpointEvery > 0 ? o->checkpointEvery : std::max(1, ts.steps / 20);
    const int until = o->stopAfter >= 0 ? int(std::min<long>(o->stopAfter, ts.steps)) : ts.steps;
    ProgressBar bar("step", ts.steps, trainer.step(), o->quiet);
    TrainReport last;
    while (trainer.step() < until) {
      const int next = int(std::min<long>(until, (trainer.step() / every + 1) * every));
      trainer.run(next, [&](const TrainReport &r) {
        last = r;
        bar.update(r.step, "loss " + shortNumber(r.loss) + "  lr " + shortNumber(r.lr) +
                               "  alpha " + shortNumber(r.alpha));
      });
      if (trainer.step() < ts.steps) trainer.saveCheckpoint(ckpt);
    }
    if (trainer.step() < ts.steps) {
      std::cerr << "\nstopped after step " << trainer.step() << "; checkpoint in " << ckpt
                << " (continue with --resume)\n";
      return 0;
    }
    bar.finish("loss " + shortNumber(last.loss));
    gen.save(o->output,
             {{"train_settings", ts.describe()}, {"train_steps", std::to_string(trainer.step())}});
    std::filesystem::remove(ckpt);
    // The split the neural issue asks for (this session's steps only).
    std::printf("final_loss %.6g\nmlp_seconds %.3f\nloss_kernel_seconds %.3f\n", last.loss,
                last.mlpSeconds, last.lossSeconds);
    if (!o->quiet) std::cerr << "wrote model " << o->output << "\n";
    return 0;
  };
}

}  // namespace nuld::cli
