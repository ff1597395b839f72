#include "sampler/neural/neural_trainer.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "sampler/io/atomic_file.h"
#include "sampler/io/round_trip.h"
#include "sampler/loss/box_mass.h"
#include "sampler/loss/soft_box_loss.h"
#include "sampler/metrics/discrepancy.h"
#include "sampler/neural/network.h"
#include "sampler/optimize/schedule.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/grid_target.h"

namespace nuld {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// What one step's loss needs besides the points: the batch's targets, their
// boxes and exact masses, the sigmoid scale.
struct Batch {
  GradientPullback pullback = GradientPullback::Exact;
  std::vector<Point2> z;
  std::vector<double> gamma;
  std::vector<std::vector<Box2>> boxes;
  std::vector<std::vector<double>> masses;
  std::vector<std::shared_ptr<const Target>> targets;
  const NeuralGenerator *generator = nullptr;
  SoftBoxLossOptions options;
  double *kernelSeconds = nullptr;
};

// The soft box loss as a LibTorch autograd function: forward runs the
// sampler's kernel on each set and keeps its analytic gradient, backward
// hands that gradient on. Points leave the network unwrapped; the loss sees
// them placed into the domain (NeuralGenerator::place: the inverse CDF when
// mapped, a clamp or a pole reflection when not), and the gradient is pulled
// back through that map's Jacobian (scaled per coordinate when balanced).
struct SoftBoxLossFunction : torch::autograd::Function<SoftBoxLossFunction> {
  static torch::Tensor forward(torch::autograd::AutogradContext *ctx, torch::Tensor points,
                               const Batch *batch) {
    const auto start = Clock::now();
    const torch::Tensor x = points.detach().to(torch::kFloat64).contiguous();
    const std::int64_t B = x.size(0), n = x.size(1);
    torch::Tensor grad = torch::zeros_like(x);
    const auto *px = reinterpret_cast<const Point2 *>(x.data_ptr<double>());
    auto *pg = reinterpret_cast<Point2 *>(grad.data_ptr<double>());
    std::vector<Point2> placed(std::size_t(n), Point2{}), g(std::size_t(n), Point2{});
    std::vector<Jacobian2> jac(static_cast<std::size_t>(n));
    double loss = 0;
    for (std::int64_t b = 0; b < B; ++b) {
      for (std::int64_t i = 0; i < n; ++i)
        placed[i] = batch->generator->place(px[b * n + i], *batch->targets[b], &jac[i]);
      loss += softBoxLoss(placed, batch->boxes[b], batch->masses[b], batch->options, g);
      for (std::int64_t i = 0; i < n; ++i) {
        Point2 gi = jac[i].transposeTimes(g[i]);
        if (batch->pullback == GradientPullback::Balanced) gi = balancedPullback(gi, jac[i]);
        pg[b * n + i] = {gi.x / double(B), gi.y / double(B)};
      }
    }
    ctx->saved_data["grad"] = grad.to(points.scalar_type());
    if (batch->kernelSeconds) *batch->kernelSeconds += secondsSince(start);
    return torch::tensor(loss / double(B), torch::TensorOptions().dtype(points.scalar_type()));
  }

  static torch::autograd::variable_list backward(torch::autograd::AutogradContext *ctx,
                                                 torch::autograd::variable_list gradOutput) {
    return {ctx->saved_data["grad"].toTensor() * gradOutput[0], torch::Tensor()};
  }
};

}  // namespace

// The trainer the plugin makes (NeuralTrainer::make).
class TorchTrainer final : public NeuralTrainer {
 public:
  TorchTrainer(NeuralGenerator &generator, TrainerSettings settings);

  const TrainerSettings &settings() const override { return settings_; }
  int step() const override { return step_; }
  void run(int untilStep, const std::function<void(const TrainReport &)> &progress) override;
  double evaluate(int step) override;
  double lossAndGradient(int step) override;
  Validation validate() override;
  const std::vector<Validation> &history() const override { return history_; }
  void batchInputs(int step, std::vector<Point2> &z, std::vector<double> &gamma) const override;
  void validationInputs(std::vector<Point2> &z, std::vector<double> &gamma) const override;
  std::size_t sizeAt(int step) const override;
  std::optional<Validation> best() const override;
  void saveCheckpoint(const std::string &path) const override;
  void loadCheckpoint(const std::string &path) override;
  ResumableRun resumableRun(const std::string &model,
                            std::function<void(const TrainReport &)> progress) override;
  Validation validateAndRecord(const std::string &model) override;
  bool writeModel(const std::string &model, bool keepBest) override;

 private:
  enum class Mode { Evaluate, Gradient, Train };
  double stepLoss(int step, Mode mode);
  std::string formatLosses() const;  // "count sum" of losses since validation
  // The metadata a written model carries: settings, steps, its held-out L2.
  std::map<std::string, std::string> modelMetadata(int step, const Validation *scored) const;

  NeuralGenerator &gen_;
  TorchNet &net_;
  TrainerSettings settings_;
  std::unique_ptr<torch::optim::Adam> adam_;
  int step_ = 0;
  double mlpSeconds_ = 0, lossSeconds_ = 0;
  double lossSum_ = 0;  // training losses since the last validation
  int lossCount_ = 0;
  std::vector<Validation> history_;
};

TorchTrainer::TorchTrainer(NeuralGenerator &generator, TrainerSettings settings)
    : gen_(generator), net_(torchNet(generator)), settings_(std::move(settings)) {
  settings_.validate();
  if (settings_.shiftedSets) {
    // Any gamma makes a target of the family's kind; the shift needs its CDF map.
    const std::vector<double> gamma(gen_.gammaDimension(), 0.5);
    if (!gen_.settings().mapped ||
        !dynamic_cast<const GridTarget *>(gen_.family().target(gamma).get()))
      throw std::invalid_argument("train: shifted sets need mapped sets of a tabulated target ('" +
                                  gen_.family().spec() + "' is not one)");
  }
  const std::size_t sizes = gen_.settings().sizesTrained().size();
  if (settings_.validationSets > 0 && settings_.validationSets < sizes)
    throw std::invalid_argument("train: " + std::to_string(sizes) +
                                " training sizes need at least as many validation sets, not " +
                                std::to_string(settings_.validationSets));
  adam_ = std::make_unique<torch::optim::Adam>(
      net_.module().parameters(),
      torch::optim::AdamOptions(settings_.lrStart).betas({0.9, 0.999}).eps(1e-8).weight_decay(0));
}

double TorchTrainer::stepLoss(int step, Mode mode) {
  const TrainerSettings &s = settings_;
  const std::size_t g = gen_.gammaDimension(), B = s.batch;
  Batch batch;
  batch.generator = &gen_;
  batch.pullback = s.pullback;
  batch.targets.resize(B);
  batch.options = {linearRamp(s.alphaStart, s.alphaEnd, s.rampFraction, step, s.steps), s.cutoff};
  batch.kernelSeconds = &lossSeconds_;

  // The batch's offsets, parameters, boxes and masses: all keyed by (seed, step).
  const auto massStart = Clock::now();
  batchInputs(step, batch.z, batch.gamma);
  batch.boxes.assign(B, std::vector<Box2>(s.boxes));
  batch.masses.assign(B, std::vector<double>(s.boxes));
  for (std::size_t b = 0; b < B; ++b) {
    Rng boxRng(s.seed, hash3(0xB0C5, std::uint64_t(step), b));
    sampleBoxes(s.boxKind, boxRng, batch.boxes[b]);
    batch.targets[b] = gen_.family().target(std::span(batch.gamma).subspan(b * g, g));
    exactBoxMasses(*batch.targets[b], batch.boxes[b], batch.masses[b]);
  }
  lossSeconds_ += secondsSince(massStart);

  const auto netStart = Clock::now();
  const double kernelBefore = lossSeconds_;
  const torch::Tensor base = baseSets(gen_, batch.z, sizeAt(step));
  std::vector<const Target *> members(B);
  for (std::size_t b = 0; b < B; ++b) members[b] = batch.targets[b].get();
  const torch::Tensor residual = net_.forward(gen_, batch.z, batch.gamma, base, members);
  torch::Tensor points = base.to(residual.scalar_type()) + residual;
  if (s.shiftedSets) {
    // One offset per set, keyed by (seed, step, set); the loss wraps u.
    std::vector<double> shift(2 * B);
    for (std::size_t b = 0; b < B; ++b) {
      Rng rng(s.seed, hash3(0x5A1F7, std::uint64_t(step), b));
      shift[2 * b] = rng.uniform();
      shift[2 * b + 1] = rng.uniform();
    }
    points = points + torch::from_blob(shift.data(), {std::int64_t(B), 1, 2}, torch::kFloat64)
                          .to(points.scalar_type());
  }
  torch::Tensor loss = SoftBoxLossFunction::apply(points, &batch);
  if (mode != Mode::Evaluate) {
    adam_->zero_grad();
    loss.backward();
  }
  if (mode == Mode::Train) {
    const double lr = logLinear(s.lrStart, s.lrEnd, step, s.steps);
    for (auto &group : adam_->param_groups())
      static_cast<torch::optim::AdamOptions &>(group.options()).lr(lr);
    adam_->step();
  }
  // Network time is the step's time minus what the kernel took inside it.
  mlpSeconds_ += secondsSince(netStart) - (lossSeconds_ - kernelBefore);
  return loss.item<double>();
}

double TorchTrainer::evaluate(int step) {
  torch::NoGradGuard noGrad;
  return stepLoss(step, Mode::Evaluate);
}

double TorchTrainer::lossAndGradient(int step) { return stepLoss(step, Mode::Gradient); }

void TorchTrainer::run(int untilStep, const std::function<void(const TrainReport &)> &progress) {
  const TrainerSettings &s = settings_;
  untilStep = std::min(untilStep, s.steps);
  for (; step_ < untilStep; ++step_) {
    const double loss = stepLoss(step_, Mode::Train);
    if (!std::isfinite(loss))
      throw std::runtime_error("train: the loss became non-finite at step " +
                               std::to_string(step_ + 1) + " (learning rate " +
                               formatRoundTrip(logLinear(s.lrStart, s.lrEnd, step_, s.steps)) +
                               "): the training diverged; lower --lr");
    lossSum_ += loss;
    ++lossCount_;
    if (progress)
      progress({step_ + 1, s.steps, loss, logLinear(s.lrStart, s.lrEnd, step_, s.steps),
                linearRamp(s.alphaStart, s.alphaEnd, s.rampFraction, step_, s.steps), mlpSeconds_,
                lossSeconds_});
  }
}

std::size_t TorchTrainer::sizeAt(int step) const {
  const std::vector<std::size_t> sizes = gen_.settings().sizesTrained();
  return sizes[std::size_t(step) % sizes.size()];
}

Validation TorchTrainer::validate() {
  const TrainerSettings &s = settings_;
  if (s.validationSets == 0) throw std::logic_error("train: validation is turned off");
  const std::size_t K = s.validationSets, g = gen_.gammaDimension();
  const std::vector<std::size_t> sizes = gen_.settings().sizesTrained();
  std::vector<Point2> z;
  std::vector<double> gamma;
  validationInputs(z, gamma);
  // Pair k is scored at size k mod |sizes|. L2 falls with N, so several
  // sizes combine by the geometric mean of their means (one size: its mean).
  double score = sizes.size() == 1 ? 0 : 1;
  for (std::size_t size = 0; size < sizes.size(); ++size) {
    const std::size_t n = sizes[size];
    std::vector<Point2> zs;
    std::vector<double> gs;
    for (std::size_t k = size; k < K; k += sizes.size()) {
      zs.push_back(z[k]);
      gs.insert(gs.end(), gamma.begin() + std::ptrdiff_t(k * g),
                gamma.begin() + std::ptrdiff_t((k + 1) * g));
    }
    std::vector<Point2> points(zs.size() * n);
    gen_.generate(zs, gs, n, points);
    double sum = 0;
    for (std::size_t k = 0; k < zs.size(); ++k) {
      const auto target = gen_.family().target(std::span(gs).subspan(k * g, g));
      if (s.shiftedSets) {
        // The shift the renderer applies: through the target's CDF map.
        const auto *grid = dynamic_cast<const GridTarget *>(target.get());
        if (!grid) throw std::invalid_argument("train: shifted sets need a tabulated target");
        Rng rng(s.seed, hash3(0x5A1F7, 0xFFFFFFFFull, k + size * K));
        const Point2 d{rng.uniform(), rng.uniform()};
        for (Point2 &p : std::span(points).subspan(k * n, n)) {
          Point2 u = grid->primaryOf(p);
          u = {wrapUnit(u.x + d.x), wrapUnit(u.y + d.y)};
          p = grid->invert(u).x;
        }
      }
      sum += nonuniformL2asd(std::span(points).subspan(k * n, n), *target, s.validationGrid);
    }
    const double mean = sum / double(zs.size());
    score = sizes.size() == 1 ? mean : score * std::pow(mean, 1 / double(sizes.size()));
  }
  const Validation v{
      step_, lossCount_ > 0 ? lossSum_ / lossCount_ : std::numeric_limits<double>::quiet_NaN(),
      score};
  lossSum_ = 0;
  lossCount_ = 0;
  history_.push_back(v);
  return v;
}

void TorchTrainer::batchInputs(int step, std::vector<Point2> &z, std::vector<double> &gamma) const {
  const std::size_t B = settings_.batch, g = gen_.gammaDimension();
  Rng rng(settings_.seed, hashCombine(0x7EA1, std::uint64_t(step)));
  z.resize(B);
  gamma.resize(B * g);
  for (std::size_t b = 0; b < B; ++b) {
    z[b] = {rng.uniform(), rng.uniform()};
    for (std::size_t k = 0; k < g; ++k) gamma[b * g + k] = rng.uniform();
  }
}

void TorchTrainer::validationInputs(std::vector<Point2> &z, std::vector<double> &gamma) const {
  const std::size_t K = settings_.validationSets, g = gen_.gammaDimension();
  // A stream of their own: training batches draw from (seed, 0x7EA1 + step).
  Rng rng(settings_.seed, 0x5A11DA7Eull);
  z.resize(K);
  gamma.resize(K * g);
  for (std::size_t k = 0; k < K; ++k) {
    z[k] = {rng.uniform(), rng.uniform()};
    for (std::size_t j = 0; j < g; ++j) gamma[k * g + j] = rng.uniform();
  }
}

std::optional<Validation> TorchTrainer::best() const {
  std::optional<Validation> b;
  for (const Validation &v : history_)
    if (!b || v.l2 < b->l2) b = v;
  return b;
}

namespace {

// The history as "step loss l2;..." with round-trip precision, and back.
std::string formatHistory(const std::vector<Validation> &history) {
  std::string out;
  for (const Validation &v : history)
    out += std::to_string(v.step) + ' ' + formatRoundTrip(v.meanLoss) + ' ' +
           formatRoundTrip(v.l2) + ';';
  return out;
}

std::vector<Validation> parseHistory(const std::string &text, const std::string &path) {
  std::vector<Validation> history;
  std::istringstream in(text);
  std::string entry;
  while (std::getline(in, entry, ';')) {
    std::istringstream fields(entry);
    std::string step, loss, l2;
    Validation v;
    try {
      if (!(fields >> step >> loss >> l2)) throw std::invalid_argument("fields");
      v = {std::stoi(step), std::stod(loss), std::stod(l2)};
    } catch (const std::exception &) {
      throw std::runtime_error(path + ": validation_history entry '" + entry +
                               "' is not 'step loss l2'");
    }
    history.push_back(v);
  }
  return history;
}

}  // namespace

void TorchTrainer::saveCheckpoint(const std::string &path) const {
  ModelFile file = gen_.toModelFile({{"train_step", std::to_string(step_)},
                                     {"train_settings", settings_.describe()},
                                     {"validation_history", formatHistory(history_)},
                                     {"losses_since_validation", formatLosses()}});
  // LibTorch serializes Adam's moments to bytes; they travel inside the model
  // file (as a byte tensor packed into floats) so model and optimizer state
  // are written in one atomic rename and can never disagree.
  std::ostringstream bytes;
  torch::save(*adam_, bytes);
  std::string blob = bytes.str();
  file.metadata["adam_state_bytes"] = std::to_string(blob.size());
  blob.resize((blob.size() + 3) / 4 * 4, '\0');
  ModelTensor t{"trainer.adam_state", {std::int64_t(blob.size() / 4)}, {}};
  t.data.resize(blob.size() / 4);
  std::memcpy(t.data.data(), blob.data(), blob.size());
  file.tensors.push_back(std::move(t));
  writeModelFile(path, file);
}

void TorchTrainer::loadCheckpoint(const std::string &path) {
  const ModelFile file = readModelFile(path);
  const std::string &described = file.value("train_settings", path);
  if (described != settings_.describe())
    throw std::runtime_error(path + ": checkpoint was made with other training settings (" +
                             described + "; now " + settings_.describe() + ")");
  const auto expected = gen_.metadata();
  for (const char *key : {"arch", "n", "hidden", "family", "seed", "mapping", "training_n"}) {
    // Checkpoints from before the graph generator have no 'arch', single-size
    // ones no 'training_n'.
    const bool absent = !file.metadata.count(key);
    const std::string found = std::string(key) == "arch" && absent         ? "supplement"
                              : std::string(key) == "training_n" && absent ? ""
                                                                           : file.value(key, path);
    if (found != (expected.count(key) ? expected.at(key) : ""))
      throw std::runtime_error(path + ": checkpoint is for another network ('" + key + "' is " +
                               found + ")");
  }
  gen_.loadWeights(file, path);
  const ModelTensor &t = file.tensor("trainer.adam_state", path);
  std::string blob(t.data.size() * 4, '\0');
  std::memcpy(blob.data(), t.data.data(), blob.size());
  blob.resize(std::stoull(file.value("adam_state_bytes", path)));
  std::istringstream in(blob);
  torch::load(*adam_, in);
  step_ = std::stoi(file.value("train_step", path));
  history_ = parseHistory(file.value("validation_history", path), path);
  std::istringstream losses(file.value("losses_since_validation", path));
  if (!(losses >> lossCount_ >> lossSum_))
    throw std::runtime_error(path + ": losses_since_validation is not 'count sum'");
}

std::string TorchTrainer::formatLosses() const {
  return std::to_string(lossCount_) + ' ' + formatRoundTrip(lossSum_);
}

namespace {

// step, mean training loss since the previous row, held-out L2.
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

std::map<std::string, std::string> TorchTrainer::modelMetadata(int step,
                                                               const Validation *scored) const {
  std::map<std::string, std::string> extra = {{"train_settings", settings_.describe()},
                                              {"train_steps", std::to_string(step)}};
  if (scored) extra["validation_l2"] = formatRoundTrip(scored->l2);
  return extra;
}

Validation TorchTrainer::validateAndRecord(const std::string &model) {
  const Validation v = validate();
  if (best()->step == v.step) gen_.save(bestModelPath(model), modelMetadata(v.step, &v));
  writeValidationCurve(validationCurvePath(model), history_);
  return v;
}

ResumableRun TorchTrainer::resumableRun(const std::string &model,
                                        std::function<void(const TrainReport &)> progress) {
  const bool validating = settings_.validationSets > 0;
  ResumableRun run;
  run.unit = "step";
  run.total = settings_.steps;
  run.position = [this] { return step_; };
  run.advance = [this, model, validating, progress = std::move(progress)](int until) {
    if (validating && history_.empty()) validateAndRecord(model);  // the untrained net
    this->run(until, progress);
  };
  if (validating) run.segmentDone = [this, model] { validateAndRecord(model); };
  run.save = [this](const std::string &path) { saveCheckpoint(path); };
  run.load = [this](const std::string &path) { loadCheckpoint(path); };
  return run;
}

bool TorchTrainer::writeModel(const std::string &model, bool keepBest) {
  const bool validating = !history_.empty();
  const std::string bestPath = bestModelPath(model);
  if (keepBest && validating) {
    std::filesystem::rename(bestPath, model);
    return true;
  }
  gen_.save(model, modelMetadata(step_, validating ? &history_.back() : nullptr));
  std::filesystem::remove(bestPath);
  return false;
}

std::unique_ptr<NeuralTrainer> makeTorchTrainer(NeuralGenerator &generator,
                                                const TrainerSettings &settings) {
  return std::make_unique<TorchTrainer>(generator, settings);
}

}  // namespace nuld
