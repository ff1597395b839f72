#pragma once
// LibTorch internals of the neural generator. Only the generator's and the
// trainer's translation units (and the neural tests) include this: one file
// including <torch/torch.h> costs ~15 s and ~1 GB to compile (DESIGN.md §6).

#include <torch/torch.h>

#include "sampler/neural/neural_generator.h"

namespace nuld {

// Five fully connected layers with ReLU; the Fourier encoding e of the input
// v = (z, gamma) is the first layer's input and is concatenated to the input
// of every later layer. The last layer outputs N d residuals.
struct FourierMlpImpl : torch::nn::Module {
  FourierMlpImpl(torch::Tensor frequencies, int hidden, std::int64_t outputs);

  // v: [batch, 2 + g] -> residuals [batch, outputs], in the module's dtype.
  torch::Tensor forward(torch::Tensor v);
  torch::Tensor encode(torch::Tensor v) const;

  torch::Tensor B;  // [encodingDims / 2 (+ harmonics), 2 + g], a buffer (saved, not trained)
  torch::nn::Linear l1{nullptr}, l2{nullptr}, l3{nullptr}, l4{nullptr}, l5{nullptr};
};
TORCH_MODULE(FourierMlp);

struct NeuralGenerator::Net {
  FourierMlp mlp{nullptr};

  // The network's outputs for input rows v (no autograd): the same values
  // as mlp->forward(v) up to single-precision summation order.
  torch::Tensor residuals(const torch::Tensor &v) const;
  // The input rows (z, gamma) for K sets, in the module's dtype.
  torch::Tensor inputs(std::span<const Point2> z, std::span<const double> gamma,
                       std::size_t gammaDim) const;
};

// The base sets for the given offsets as a [K, N, 2] double tensor.
torch::Tensor baseSets(const NeuralGenerator &gen, std::span<const Point2> z);

}  // namespace nuld
