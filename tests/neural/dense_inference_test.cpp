// The single-row MLP forward pass against a plain double-precision oracle,
// on layer sizes that are not multiples of the vector width.

#include "sampler/neural/dense_inference.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sampler/sequences/rng.h"

namespace nuld {
namespace {

struct Layer {
  std::vector<float> w, b;
  int in, out;
};

TEST(DenseInference, MatchesADoublePrecisionOracle) {
  Rng rng(17);
  auto uniform = [&] { return float(2 * rng.uniform() - 1); };
  const int e = 6;                                   // encoding width
  const std::vector<int> widths = {37, 53, 29, 70};  // hidden sizes, then the output
  std::vector<Layer> layers;
  int in = e;
  for (std::size_t l = 0; l < widths.size(); ++l) {
    Layer L{{}, {}, in, widths[l]};
    for (int k = 0; k < L.in * L.out; ++k) L.w.push_back(uniform() / std::sqrt(float(in)));
    for (int k = 0; k < L.out; ++k) L.b.push_back(0.1f * uniform());
    layers.push_back(L);
    in = widths[l] + e;
  }
  std::vector<float> encoding(e);
  for (float &v : encoding) v = uniform();

  std::vector<DenseLayer> views;
  for (const Layer &L : layers) views.push_back({L.w.data(), L.b.data(), L.in, L.out});
  const std::vector<float> got = fourierMlpForward(views, encoding);

  std::vector<double> x(encoding.begin(), encoding.end());
  for (std::size_t l = 0; l < layers.size(); ++l) {
    const Layer &L = layers[l];
    std::vector<double> y(L.out);
    for (int o = 0; o < L.out; ++o) {
      double s = L.b[o];
      for (int i = 0; i < L.in; ++i) s += double(L.w[std::size_t(o) * L.in + i]) * x[i];
      y[o] = l + 1 < layers.size() ? std::max(s, 0.0) : s;
    }
    if (l + 1 < layers.size()) y.insert(y.end(), encoding.begin(), encoding.end());
    x = y;
  }
  ASSERT_EQ(got.size(), x.size());
  double largest = 0;
  for (double v : x) largest = std::max(largest, std::abs(v));
  ASSERT_GT(largest, 0.1);  // the oracle is not trivially zero
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(got[i], x[i], 1e-5 * largest) << i;
}

TEST(DenseInference, RejectsLayersThatDoNotChain) {
  const std::vector<float> w(4 * 3, 0.0f), b(4, 0.0f), encoding(3, 1.0f);
  const std::vector<DenseLayer> bad = {{w.data(), b.data(), 3, 4}, {w.data(), b.data(), 3, 1}};
  EXPECT_THROW(fourierMlpForward(bad, encoding), std::invalid_argument);
  EXPECT_THROW(fourierMlpForward({}, encoding), std::invalid_argument);
}

}  // namespace
}  // namespace nuld
