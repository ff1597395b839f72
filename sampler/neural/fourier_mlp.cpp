#include "sampler/neural/fourier_mlp.h"

#include <cmath>
#include <numbers>

#include "sampler/sequences/rng.h"

namespace nuld {

torch::Tensor drawFrequencies(int rows, int cols, double sigma, std::uint64_t seed) {
  torch::Tensor b = torch::empty({rows, cols}, torch::kFloat32);
  auto a = b.accessor<float, 2>();
  Rng rng(seed, 0xB);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double u1 = 1 - rng.uniform(), u2 = rng.uniform();
      a[r][c] = float(sigma * std::sqrt(-2 * std::log(u1)) * std::cos(2 * std::numbers::pi * u2));
    }
  return b;
}

torch::Tensor zHarmonicFrequencies(int k, int cols) {
  const int rows = ((2 * k + 1) * (2 * k + 1) - 1) / 2;
  torch::Tensor b = torch::zeros({rows, cols}, torch::kFloat32);
  auto a = b.accessor<float, 2>();
  int r = 0;
  for (int fx = 0; fx <= k; ++fx)
    for (int fy = -k; fy <= k; ++fy)
      if (fx > 0 || fy > 0) a[r][0] = float(fx), a[r][1] = float(fy), ++r;
  return b;
}

FourierMlpImpl::FourierMlpImpl(torch::Tensor frequencies, int hidden, std::int64_t outputs) {
  B = register_buffer("B", std::move(frequencies));
  const std::int64_t e = B.size(0) * 2;
  l1 = register_module("l1", torch::nn::Linear(e, hidden));
  l2 = register_module("l2", torch::nn::Linear(hidden + e, hidden));
  l3 = register_module("l3", torch::nn::Linear(hidden + e, hidden));
  l4 = register_module("l4", torch::nn::Linear(hidden + e, hidden));
  l5 = register_module("l5", torch::nn::Linear(hidden + e, outputs));
  // Zero residuals: the untrained generator is its base set (supplement §1).
  torch::NoGradGuard noGrad;
  l5->weight.zero_();
  l5->bias.zero_();
}

torch::Tensor fourierFeatures(const torch::Tensor &v, const torch::Tensor &B) {
  const torch::Tensor angle = (2 * std::numbers::pi) * torch::matmul(v, B.t());
  return torch::cat({torch::cos(angle), torch::sin(angle)}, 1);
}

torch::Tensor FourierMlpImpl::encode(torch::Tensor v) const { return fourierFeatures(v, B); }

torch::Tensor FourierMlpImpl::forward(torch::Tensor v) {
  const torch::Tensor e = encode(v);
  torch::Tensor h = torch::relu(l1(e));
  h = torch::relu(l2(torch::cat({h, e}, 1)));
  h = torch::relu(l3(torch::cat({h, e}, 1)));
  h = torch::relu(l4(torch::cat({h, e}, 1)));
  return l5(torch::cat({h, e}, 1));
}

}  // namespace nuld
