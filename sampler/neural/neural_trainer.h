#pragma once
// Training of the neural generator (supplement §1; docs/architecture.md,
// "The neural generator"): each step
// draws a batch of (z, gamma) pairs, generates their sets, and moves the
// network's weights by LibTorch's Adam on the mean soft box discrepancy of the
// sets against their targets. The loss enters LibTorch's autograd as a custom
// function whose backward pass is the sampler core's analytic gradient
// (softBoxLoss), so no autodiff runs over the N x M point-box pairs.
//
// Every random choice of step t is keyed by (seed, t), so a run resumed from a
// checkpoint continues exactly as the uninterrupted run would.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sampler/loss/boxes.h"
#include "sampler/neural/neural_generator.h"
#include "sampler/optimize/resumable_run.h"

namespace nuld {

// How the loss gradient with respect to a placed point x becomes one with
// respect to the net's output u in mapped mode (x = T(u), the target's
// inverse CDF). Exact is J^T g, the true gradient. Where T stretches (dark
// rows of a map, the quarter-disc's rim) J's columns grow like 1/density, so
// a few points dominate every shared weight's gradient and Adam, which normalizes
// per weight rather than per point, starves the rest. Balanced divides each
// u-coordinate's component by the length of its Jacobian column: the
// derivative along the unit direction that coordinate moves x in. It is a
// positive per-coordinate rescaling, so still a descent direction; it leaves
// unmapped training (J = +-identity) unchanged. Balanced is the default
// because exact training let the stretched points ruin the sets on an
// environment map (tools/experiments/neural_generator.md, "Mapped training:
// exact or balanced gradient").
enum class GradientPullback { Exact, Balanced };
inline constexpr auto kGradientPullbackNames = enumTable<GradientPullback>(
    "gradient pull-back",
    {{"exact", GradientPullback::Exact}, {"balanced", GradientPullback::Balanced}});
constexpr const auto &enumNames(GradientPullback) { return kGradientPullbackNames; }
inline GradientPullback parseGradientPullback(const std::string &name) {
  return kGradientPullbackNames.parse(name);
}

struct TrainerSettings {
  int steps = 2000;
  std::size_t batch = 16;
  std::size_t boxes = 8192;  // per set and step
  BoxKind boxKind = BoxKind::MultipleCorner;
  double lrStart = 5e-4, lrEnd = 5e-7;  // log-linear decay
  double alphaStart = 20, alphaEnd = 2000, rampFraction = 0.5;
  double cutoff = 36;
  GradientPullback pullback = GradientPullback::Balanced;
  std::uint64_t seed = 0;
  // Held-out validation (ours, not the supplement's): this many (z, gamma)
  // pairs, drawn once from the seed's own stream and never a training batch,
  // scored by the grid L2 discrepancy at this resolution; 0 sets: none.
  std::size_t validationSets = 8;
  int validationGrid = 128;
  // Ours: train (and validate) the sets as the renderer deals them out for
  // a lobe table, Cranley-Patterson shifted in the target's primary space
  // by a random offset per set (mapped mode): the loss then rewards sets
  // that stay good under any shift, the only randomization that keeps the
  // estimate unbiased for any table (tools/experiments/neural_lobe_model.md,
  // "The graph generator in primary space").
  bool shiftedSets = false;

  std::string describe() const;  // "key=value ..."; checkpoints must match it
  void validate() const;         // throws std::invalid_argument naming the setting
};

struct TrainReport {
  int step = 0, steps = 0;  // step just completed (1-based)
  double loss = 0;          // mean over the batch
  double lr = 0, alpha = 0;
  double mlpSeconds = 0,
         lossSeconds = 0;  // cumulative: network (forward, backward, Adam) vs loss kernel
};

// One validation: after `step` steps, the mean training loss since the
// previous validation (NaN when no step ran in between) and the held-out L2.
struct Validation {
  int step = 0;
  double meanLoss = 0, l2 = 0;
};

// The trainer is LibTorch code: make() gets one from the plugin
// (neural_runtime.h); the generator must outlive it.
class NeuralTrainer {
 public:
  static std::unique_ptr<NeuralTrainer> make(NeuralGenerator &generator,
                                             const TrainerSettings &settings);
  virtual ~NeuralTrainer() = default;

  virtual const TrainerSettings &settings() const = 0;
  virtual int step() const = 0;
  // Runs steps [step(), untilStep); `progress` is called after each.
  virtual void run(int untilStep,
                   const std::function<void(const TrainReport &)> &progress = {}) = 0;
  // Step `step`'s loss (its batch, boxes and alpha) without changing the
  // weights; lossAndGradient also leaves dL/dw in the parameters' grad().
  virtual double evaluate(int step) = 0;
  virtual double lossAndGradient(int step) = 0;

  // The mean grid L2 discrepancy (nonuniformL2asd, each set against its own
  // target) of the sets the current weights give at the held-out pairs,
  // appended to history(). The soft box loss changes with alpha along the
  // schedule and sees fresh z every step; this measure does neither, so it
  // shows when more steps stop helping at unseen z. Throws when
  // validationSets is 0.
  virtual Validation validate() = 0;
  virtual const std::vector<Validation> &history() const = 0;
  // Step `step`'s training pairs: batch offsets and their gammas, keyed by
  // (seed, step).
  virtual void batchInputs(int step, std::vector<Point2> &z, std::vector<double> &gamma) const = 0;
  // The held-out pairs validate() scores: validationSets offsets and their
  // gammas (gammaDimension() each), a pure function of the settings.
  virtual void validationInputs(std::vector<Point2> &z, std::vector<double> &gamma) const = 0;
  // The set size step `step` trains at: the model's training sizes in turn.
  virtual std::size_t sizeAt(int step) const = 0;
  // The validation with the smallest L2 so far; nullopt before the first.
  virtual std::optional<Validation> best() const = 0;

  // The model file plus the optimizer state and the validation history; atomic.
  virtual void saveCheckpoint(const std::string &path) const = 0;
  // Throws naming the file when it is unreadable or made with other settings.
  virtual void loadCheckpoint(const std::string &path) = 0;

  // Training toward the model file `model` as a run for driveRun (resumable
  // by the checkpoints above). When validating, the untrained net is scored
  // before the first step and the weights after every segment, each through
  // validateAndRecord.
  virtual ResumableRun resumableRun(const std::string &model,
                                    std::function<void(const TrainReport &)> progress = {}) = 0;
  // validate(), then records it beside `model`: MODEL.validation.csv, the
  // held-out curve (rewritten whole), and MODEL.best, the weights, when they
  // are the best so far. MODEL.best is written before the checkpoint that
  // records the validation, so a resumed run never lacks its file.
  virtual Validation validateAndRecord(const std::string &model) = 0;
  // Writes `model`: the best held-out weights (MODEL.best) when keepBest and
  // validating, else the current ones; removes MODEL.best. Returns whether
  // the best was kept.
  virtual bool writeModel(const std::string &model, bool keepBest) = 0;
  static std::string bestModelPath(const std::string &model) { return model + ".best"; }
  static std::string validationCurvePath(const std::string &model) {
    return model + ".validation.csv";
  }
};

}  // namespace nuld
