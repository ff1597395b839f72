#pragma once
// The network behind a NeuralGenerator, whichever its architecture. LibTorch
// internals: only the plugin's translation units (sampler/neural/
// neural_runtime.h) and the neural tests include this.

#include <torch/torch.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sampler/metrics/nonuniform_l2.h"
#include "sampler/neural/fourier_mlp.h"
#include "sampler/neural/graph_net.h"
#include "sampler/neural/neural_generator.h"
#include "sampler/neural/neural_trainer.h"
#include "sampler/neural/torus_graph.h"

namespace nuld {

struct TorchNet final : NeuralNet {
  FourierMlp mlp{nullptr};  // NetworkArch::Supplement
  GraphNet graph{nullptr};  // NetworkArch::Graph
  // Graph only: the rotated base set's neighbour graph at the model's n (the
  // same for every z) and its index tensor [N k]. An Owen base's sets have graphs of their
  // own (built in forward()) with the same k.
  TorusGraph torus;
  torch::Tensor neighbours;
  // Graph with discrepancyGradient and a family without gamma (one target):
  // the objective whose gradient the points see, built with the generator.
  std::shared_ptr<const NonuniformL2asd> objective;

  // The one module that holds the weights (parameters, buffers, dtype).
  torch::nn::Module &module();
  const torch::nn::Module &module() const;

  // The residuals of K sets, [K, N, 2] in the module's dtype; they carry
  // autograd unless a NoGradGuard is active. `base` is baseSets(gen, z);
  // `members` the family's target at each set's gamma (K of them, made
  // once by the caller: a Disney lobe's table costs milliseconds, and every
  // stage reads it).
  torch::Tensor forward(const NeuralGenerator &gen, std::span<const Point2> z,
                        std::span<const double> gamma, const torch::Tensor &base,
                        std::span<const Target *const> members);

  // NeuralNet
  std::size_t parameterCount() const override;
  std::vector<ModelTensor> tensors() const override;
  void loadWeights(const ModelFile &file, const std::string &path) override;
  void rawPoints(const NeuralGenerator &gen, std::span<const Point2> z,
                 std::span<const double> gamma, std::size_t n,
                 std::span<const Target *const> members, std::span<Point2> out) const override;

  // Supplement only: the network's outputs for input rows v (no autograd):
  // the same values as mlp->forward(v) up to single-precision summation order.
  torch::Tensor residuals(const torch::Tensor &v) const;
  // Supplement only: the input rows (z, gamma) for K sets, in the module's dtype.
  torch::Tensor inputs(std::span<const Point2> z, std::span<const double> gamma,
                       std::size_t gammaDim) const;
  // Graph only: the per-point and per-edge inputs ([K, N, F], [K, N, k, E],
  // module dtype) of K sets whose current raw points are `points` ([K, N,
  // 2] double: the base set plus the residuals of earlier stages). `graphs`:
  // each set's neighbour graph, or empty for the shared `torus`; `members`
  // and `objectives` each set's target and, with discrepancyGradient, the
  // objective whose gradient its points see.
  std::pair<torch::Tensor, torch::Tensor> graphInputs(
      const NeuralGenerator &gen, std::span<const double> gamma, const torch::Tensor &points,
      const std::vector<TorusGraph> &graphs, std::span<const Target *const> members,
      std::span<const NonuniformL2asd *const> objectives) const;
};

// The untrained network `gen` describes (its settings and family set);
// `base` is its rotated base set at offset 0.
std::unique_ptr<TorchNet> makeTorchNet(const NeuralGenerator &gen, std::span<const Point2> base);
// The trainer of neural_trainer.cpp.
std::unique_ptr<NeuralTrainer> makeTorchTrainer(NeuralGenerator &generator,
                                                const TrainerSettings &settings);

// The LibTorch network of a generator (every generator's in a process
// that has the plugin's code).
inline TorchNet &torchNet(NeuralGenerator &gen) { return static_cast<TorchNet &>(gen.net()); }
inline const TorchNet &torchNet(const NeuralGenerator &gen) {
  return static_cast<const TorchNet &>(gen.net());
}

// What the plugin's translation units share (torch_net.cpp: the network
// and its residuals; graph_inputs.cpp: the graph generator's inputs).

// The graph generator's input widths: per point the torus harmonics of u,
// the placed point x, three Jacobian features, log N, and gamma raw and
// Fourier-encoded; per edge the neighbour's offset in u and in x.
std::int64_t graphNodeFeatures(const NeuralSettings &s, std::size_t gammaDim);
inline constexpr std::int64_t kGraphEdgeFeatures = 4;
// The grid of the L2 objective whose gradient --discrepancy-gradient feeds
// (exact on grid targets' own cells; 64^2 cells for closed-form ones).
inline constexpr int kGradientGrid = 64;

// The base sets of n points (0: the model's n) for the given offsets as a
// [K, n, 2] double tensor.
torch::Tensor baseSets(const NeuralGenerator &gen, std::span<const Point2> z, std::size_t n = 0);

}  // namespace nuld
