#pragma once
// Inference of the generator's MLP one input row at a time, without LibTorch.
// For a single row LibTorch's GEMM packs every weight matrix before using it
// once, which doubles the memory traffic of a net whose weights (30 MB at
// hidden 1024, N 2048) do not fit in cache; a plain matrix-vector product
// streams each weight once, over both cores. Used for small batches; large
// batches, where GEMM reuses what it packs, stay with LibTorch.

#include <span>
#include <vector>

namespace nuld {

// A fully connected layer y = W x + b, W row-major [outputs x inputs].
struct DenseLayer {
  const float *weight = nullptr;
  const float *bias = nullptr;
  int inputs = 0, outputs = 0;
};

// The Fourier MLP's forward pass for one row: `encoding` (e) is the first
// layer's input and is appended to every later layer's input; ReLU after
// every layer but the last. Returns the last layer's outputs.
std::vector<float> fourierMlpForward(std::span<const DenseLayer> layers,
                                     std::span<const float> encoding);

}  // namespace nuld
