#pragma once
// LibTorch internals of the supplement's network. Only the neural translation
// units (and the neural tests) include this: one file including
// <torch/torch.h> costs ~15 s and ~1 GB to compile.

#include <torch/torch.h>

#include <cstdint>

namespace nuld {

// B ~ N(0, sigma^2) from our own counter-based generator (Box-Muller), so a
// seed gives the same encoding on every machine and LibTorch version.
torch::Tensor drawFrequencies(int rows, int cols, double sigma, std::uint64_t seed);

// The integer frequencies (a, b) of z with max(|a|, |b|) <= k, one of each
// +- pair (a > 0, or a = 0 and b > 0); gamma's columns are 0.
torch::Tensor zHarmonicFrequencies(int k, int cols);

// The Fourier features [cos 2 pi v B^T, sin 2 pi v B^T] of the rows of v:
// the supplement's encoding of (z, gamma), and the graph generator's of gamma.
torch::Tensor fourierFeatures(const torch::Tensor &v, const torch::Tensor &B);

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

}  // namespace nuld
