#include "sampler/neural/dense_inference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>

namespace nuld {
namespace {

// One output: b + w . x in single precision with 16 partial sums (one
// vector register), summed in a fixed order: deterministic on any thread
// count.
float dot(const float *w, const float *x, int n) {
  constexpr int kLanes = 16;
  float acc[kLanes] = {};
  int i = 0;
  for (; i + kLanes <= n; i += kLanes)
    for (int j = 0; j < kLanes; ++j) acc[j] += w[i + j] * x[i + j];
  for (; i < n; ++i) acc[i % kLanes] += w[i] * x[i];
  for (int width = kLanes / 2; width > 0; width /= 2)
    for (int j = 0; j < width; ++j) acc[j] += acc[j + width];
  return acc[0];
}

void apply(const DenseLayer &layer, const float *x, float *y, bool relu) {
  tbb::parallel_for(tbb::blocked_range<int>(0, layer.outputs, 64), [&](const auto &r) {
    for (int o = r.begin(); o < r.end(); ++o) {
      const float v =
          layer.bias[o] + dot(layer.weight + std::size_t(o) * layer.inputs, x, layer.inputs);
      y[o] = relu ? std::max(v, 0.0f) : v;
    }
  });
}

}  // namespace

std::vector<float> fourierMlpForward(std::span<const DenseLayer> layers,
                                     std::span<const float> encoding) {
  if (layers.empty()) throw std::invalid_argument("fourierMlpForward: no layers");
  const int e = int(encoding.size());
  if (layers[0].inputs != e)
    throw std::invalid_argument("fourierMlpForward: the first layer does not take the encoding");
  // x = [h, e]: the encoding sits after the hidden activations.
  std::vector<float> x(encoding.begin(), encoding.end()), y;
  for (std::size_t l = 0; l < layers.size(); ++l) {
    const DenseLayer &layer = layers[l];
    if (layer.inputs != int(x.size()))
      throw std::invalid_argument("fourierMlpForward: layer sizes do not chain");
    const bool last = l + 1 == layers.size();
    y.resize(std::size_t(layer.outputs) + (last ? 0 : e));
    apply(layer, x.data(), y.data(), !last);
    if (!last) std::copy(encoding.begin(), encoding.end(), y.begin() + layer.outputs);
    std::swap(x, y);
  }
  return x;
}

}  // namespace nuld
