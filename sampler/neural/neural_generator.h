#pragma once
// The neural generator of the supplement §1 (docs/architecture.md, "The
// neural generator"): an MLP that maps a
// Cranley-Patterson offset z and a distribution parameter gamma to the
// residuals of N points, added to a base set (the first N Sobol points rotated
// by z: wrapped on the square, unwrapped for directions; or, for the graph
// generator, Owen-scrambled by a hash of z: BaseRandomization). The last layer
// starts at zero, so an untrained generator returns its base set.
//
// Two architectures share the base set, the mappings, the loss, the model
// files and the backends: the supplement's MLP (fourier_mlp.h), which maps
// (z, gamma) to all N x 2 residuals at once, and the graph generator
// (graph_net.h, ours), which computes each point's residual with weights
// shared by all points, from the point's position and its neighbours in the
// base set.
//
// This header does not include LibTorch; the networks live behind
// `NeuralNet`, which the LibTorch plugin implements (sampler/neural/
// neural_runtime.h: a process that makes no neural sets never loads LibTorch).

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "sampler/neural/model_file.h"
#include "sampler/point.h"
#include "sampler/targets/target_family.h"

namespace nuld {

// Which network computes the residuals.
enum class NetworkArch {
  Supplement,  // the supplement's five-layer MLP of (z, gamma)
  Graph,       // ours: per-point message passing over the base set's k-NN graph
};
inline constexpr auto kNetworkArchNames = enumTable<NetworkArch>(
    "network architecture",
    {{"supplement", NetworkArch::Supplement}, {"graph", NetworkArch::Graph}});
constexpr const auto &enumNames(NetworkArch) { return kNetworkArchNames; }
inline NetworkArch parseNetworkArch(const std::string &name) {
  return kNetworkArchNames.parse(name);
}

// How offset z randomizes the base set the residuals are added to.
enum class BaseRandomization {
  // The supplement's: the first N Sobol points rotated by z (Cranley-
  // Patterson). Each point is uniform, but the rotation moves the whole set
  // rigidly, so its 1D projections stay a shifted lattice: on smooth
  // integrands its error variance is far above Owen scrambling's
  // (tools/experiments/neural_generator.md, "The graph generator"), and a
  // network would have to undo that.
  Rotated,
  // Ours, graph only: the first N Sobol points Owen-scrambled with a seed
  // hashed from z (and the model's seed). The sets start as good as the
  // baseline's; the network only refines them. A point's neighbourhood then
  // changes with z, so the neighbour graph is built per set.
  Owen,
};
inline constexpr auto kBaseRandomizationNames = enumTable<BaseRandomization>(
    "base randomization",
    {{"rotated", BaseRandomization::Rotated}, {"owen", BaseRandomization::Owen}});
constexpr const auto &enumNames(BaseRandomization) { return kBaseRandomizationNames; }
inline BaseRandomization parseBaseRandomization(const std::string &name) {
  return kBaseRandomizationNames.parse(name);
}

struct NeuralSettings {
  NetworkArch arch = NetworkArch::Supplement;
  // Points per set: the supplement's network emits exactly n; the graph
  // generator (weights shared by all points) makes sets of any size, n being
  // the size generate() makes by default.
  std::size_t n = 256;
  // Graph only: the set sizes training cycles through, one per step (empty:
  // n alone; otherwise n is the first of them). Recorded in the model file,
  // so users can tell the sizes it learned from those it extrapolates to.
  std::vector<std::size_t> trainingNs;
  // Supplement: the width of the four hidden layers (64/256/512/1024 in the
  // paper). Graph: the width of each point's state.
  int hidden = 256;
  // Graph only: neighbours per point, message-passing rounds, and the order
  // of the torus harmonics that encode a point's position u (every integer
  // frequency pair (a, b) with max(|a|, |b|) <= positionHarmonics).
  int neighbours = 8;
  int rounds = 3;
  int positionHarmonics = 2;
  // Graph only: stages of the generator, each adding a residual computed
  // from the points the previous stages left (the same weights every
  // stage), and whether each point also sees the gradient of its set's grid
  // L2 discrepancy at its current position (so a stage can act as a learned
  // descent step rather than guess the direction from the neighbourhood).
  int stages = 1;
  bool discrepancyGradient = false;
  // Graph only (ours): each stage's residuals lose their mean over the set,
  // so no stage moves a set as a whole and each set keeps its base set's
  // mean in u (tools/experiments/neural_lobe_model.md, "The graph generator in
  // primary space"). A set's mean error is what a smooth integrand sees.
  bool centred = false;
  BaseRandomization base = BaseRandomization::Rotated;
  double sigma = 0.1;     // standard deviation of the Fourier frequencies B
  int encodingDims = 32;  // [cos 2 pi B v, sin 2 pi B v]: B has encodingDims / 2 rows
  // Ours, not the supplement's (0 = off): B also gets the rows (a, b, 0...)
  // for every integer pair with max(|a|, |b|) <= zHarmonics (one of each +-
  // pair), the Fourier basis of the torus z lives on. The base set moves
  // rigidly with z, so a point's best correction is a function of where z
  // has carried it, periodic in z; these rows let the last layers combine
  // that directly. The supplement's Gaussian rows (sigma 0.1: nearly linear
  // in z) barely tell nearby offsets apart
  // (tools/experiments/neural_generator.md, "Torus harmonics and offset
  // ranges").
  int zHarmonics = 0;
  // Ours, a diagnostic (1 = the supplement's): the base set is Sobol rotated
  // by offsetRange * z, so offsets span [0, offsetRange)^2 while the net
  // still sees z in [0, 1)^2. It measures how the quality of one network's
  // sets depends on how much of the offset torus it must cover
  // (tools/experiments/neural_generator.md, "Torus harmonics and offset
  // ranges"). Below 1 the sets are not randomized over the torus: each point
  // stays in a small box, so estimates from them are biased. Not for rendering.
  double offsetRange = 1;
  std::string family;      // a TargetFamily spec
  std::uint64_t seed = 0;  // draws B and the initial weights
  // Mapped: the net's points are u in the unit square (wrapped toroidally)
  // and the set is T(u), T the target's inverse CDF, so the untrained net
  // gives inverse-CDF Sobol and training learns corrections (the direct
  // optimizer's density mapping; docs/architecture.md, "The direct
  // optimizer"). Unmapped: the points are the set itself (see wrapToDomain).
  bool mapped = true;

  // Throws std::invalid_argument naming the bad setting.
  void validate() const;
  // The settings a model file's metadata records, validated, and checked
  // against the weights the file holds before any network is built. Throws
  // std::runtime_error naming the file and the key.
  static NeuralSettings fromModelFile(const ModelFile &file, const std::string &path);
  // The sizes training uses: trainingNs, or {n}.
  std::vector<std::size_t> sizesTrained() const;
};

// J^T g (`pulled`) with component k divided by |column k of J|: the
// derivative along the unit direction that u's coordinate k moves x in (the
// trainer's balanced pull-back, GradientPullback). A coordinate whose column
// is zero or not finite moves x nowhere useful and gets 0.
Point2 balancedPullback(Point2 pulled, const Jacobian2 &j);

class NeuralGenerator;

// A generator's network, whichever its architecture: what the generator
// needs of it, implemented by the LibTorch plugin (sampler/neural/network.h).
class NeuralNet {
 public:
  virtual ~NeuralNet() = default;
  virtual std::size_t parameterCount() const = 0;
  // Buffers then parameters, as float32 (the model file's tensors).
  virtual std::vector<ModelTensor> tensors() const = 0;
  // Copies the weights of `file` (read from `path`), checking each tensor's
  // shape; throws std::runtime_error naming the file and the tensor.
  virtual void loadWeights(const ModelFile &file, const std::string &path) = 0;
  // The raw points of K = z.size() sets of n points (base set plus
  // residuals, before NeuralGenerator::place), without autograd. `members`
  // holds each set's target.
  virtual void rawPoints(const NeuralGenerator &gen, std::span<const Point2> z,
                         std::span<const double> gamma, std::size_t n,
                         std::span<const Target *const> members, std::span<Point2> out) const = 0;
};

class NeuralGenerator {
 public:
  explicit NeuralGenerator(const NeuralSettings &settings);  // untrained
  // When load() builds the network: at once (weights that do not fit it are
  // refused by load itself), or on its first use (a render whose banks are
  // all in the set cache then never loads LibTorch, neural_runtime.h; such
  // weights are refused by the first generate(), naming the file).
  enum class NetworkLoad { Now, OnFirstUse };
  // Throws std::runtime_error naming the file for unreadable, truncated or
  // foreign files and for metadata that does not rebuild a network.
  static NeuralGenerator load(const std::string &path, NetworkLoad when = NetworkLoad::Now);
  // Weights plus everything needed to rebuild the net; `extra` metadata
  // (training settings, step) is stored alongside. Atomic.
  void save(const std::string &path, const std::map<std::string, std::string> &extra = {}) const;
  // What the file's metadata says of the network (format, N, family, ...).
  std::map<std::string, std::string> metadata() const;
  // The same as an in-memory file (the trainer adds its optimizer state).
  ModelFile toModelFile(const std::map<std::string, std::string> &extra = {}) const;
  // Copies the weights of a file written for this same network (checked
  // against settings()); throws naming `path`.
  void loadWeights(const ModelFile &file, const std::string &path);

  NeuralGenerator(NeuralGenerator &&) noexcept;
  NeuralGenerator &operator=(NeuralGenerator &&) noexcept;
  ~NeuralGenerator();

  const NeuralSettings &settings() const { return settings_; }
  const TargetFamily &family() const { return *family_; }
  Domain domain() const { return family_->domain(); }
  std::size_t gammaDimension() const { return family_->gammaDimension(); }
  std::size_t parameterCount() const;
  // The checksum of the file load() read (ModelFile::checksum; 0 for a new
  // generator): the same value means the same weights.
  std::uint64_t fileChecksum() const { return fileChecksum_; }

  // Whether generate() makes sets of any size (the graph generator) or of
  // settings().n only (the supplement's network).
  bool anySize() const { return settings_.arch == NetworkArch::Graph; }
  // Throws std::invalid_argument (naming the model's sizes) unless sets of n
  // points can be made.
  void checkSize(std::size_t n) const;

  // The base set for offset z, of out.size() points (checkSize): the first N
  // Sobol points rotated by offsetRange * z (wrapped on the square, not for
  // directions), or Owen-scrambled by a hash of z (BaseRandomization::Owen).
  void baseSet(Point2 z, std::span<Point2> out) const;
  // Empty for the supplement's full offset range; otherwise why the sets are
  // not randomized (naming --offset-range and its value), for the callers
  // that refuse or flag such models.
  std::string notRandomizedReason() const;
  // Where a raw network point lands: T(u) (mapped) or wrapToDomain (not),
  // with d(out)/d(raw) for the loss gradient. `target` is the family's
  // member for the set's gamma. Unmapped on the square the point is clamped
  // and training passes the gradient straight through the clamp (as the
  // direct optimizer's `clamp` mapping does: the loss is measured at the
  // clamped point). A toroidal wrap instead joins opposite edges of the
  // square, which for most targets are unlike (the quarter-disc's densest
  // edge meets its empty corner); in training it did not learn
  // (tools/experiments/implementation_notes.md).
  Point2 place(Point2 raw, const Target &target, Jacobian2 *jacobian = nullptr) const;

  // K = z.size() sets at once: set k uses z[k] and gamma[k g, (k + 1) g);
  // out receives K n points in the domain (n = settings().n unless given;
  // checkSize).
  void generate(std::span<const Point2> z, std::span<const double> gamma,
                std::span<Point2> out) const;
  // `member`, when given, is the family's target at `memberGamma`, which the
  // sets with that gamma use instead of building it again (a renderer has
  // its tables already).
  void generate(std::span<const Point2> z, std::span<const double> gamma, std::size_t n,
                std::span<Point2> out, const Target *member = nullptr,
                std::span<const double> memberGamma = {}) const;
  // K sets of n points (0: settings().n) for K offsets drawn from `seed`,
  // all with the same gamma (and `member`, when given, its target).
  PointSet generateSets(std::size_t instances, std::uint64_t seed, std::span<const double> gamma,
                        std::size_t n = 0, const Target *member = nullptr) const;

  NeuralNet &net() { return network(); }
  const NeuralNet &net() const { return network(); }

 private:
  NeuralSettings settings_;
  std::unique_ptr<const TargetFamily> family_;
  std::vector<Point2> sobol_;  // the first n Sobol points (the rotated base)
  NeuralGenerator(const NeuralSettings &settings, NetworkLoad when);
  // The network, built (and given pendingWeights_) on the first call.
  NeuralNet &network() const;
  mutable std::unique_ptr<NeuralNet> net_;
  // load()'s file and its path, until the network that takes the weights is built.
  mutable std::optional<ModelFile> pendingWeights_;
  std::string path_;
  std::unique_ptr<std::mutex> netLock_ = std::make_unique<std::mutex>();
  std::uint64_t fileChecksum_ = 0;
};

}  // namespace nuld
