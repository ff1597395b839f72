// The LibTorch network behind a NeuralGenerator (network.h): building it,
// its residuals, its weights; part of the plugin (neural_runtime.h).

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sampler/neural/dense_inference.h"
#include "sampler/neural/network.h"

namespace nuld {

std::unique_ptr<TorchNet> makeTorchNet(const NeuralGenerator &gen, std::span<const Point2> base) {
  const NeuralSettings &s = gen.settings();
  const std::size_t gammaDim = gen.gammaDimension();
  auto net = std::make_unique<TorchNet>();
  torch::manual_seed(s.seed);  // LibTorch's default initialization of the hidden layers
  if (s.arch == NetworkArch::Graph) {
    const torch::Tensor B = drawFrequencies(s.encodingDims / 2, int(gammaDim), s.sigma, s.seed);
    net->graph =
        GraphNet(B, graphNodeFeatures(s, gammaDim), kGraphEdgeFeatures, s.hidden, s.rounds);
    net->torus = buildTorusGraph(base, std::size_t(s.neighbours));
    const std::int64_t n = std::int64_t(s.n), k = std::int64_t(net->torus.k);
    net->neighbours =
        torch::from_blob(net->torus.neighbours.data(), {n * k}, torch::kInt64).clone();
    if (s.discrepancyGradient && gammaDim == 0)
      net->objective =
          std::make_shared<const NonuniformL2asd>(*gen.family().target({}), kGradientGrid);
    return net;
  }
  torch::Tensor B = drawFrequencies(s.encodingDims / 2, int(2 + gammaDim), s.sigma, s.seed);
  if (s.zHarmonics > 0) B = torch::cat({B, zHarmonicFrequencies(s.zHarmonics, int(2 + gammaDim))});
  net->mlp = FourierMlp(B, s.hidden, std::int64_t(2 * s.n));
  return net;
}

torch::nn::Module &TorchNet::module() {
  return graph ? static_cast<torch::nn::Module &>(*graph) : *mlp;
}

const torch::nn::Module &TorchNet::module() const {
  return graph ? static_cast<const torch::nn::Module &>(*graph) : *mlp;
}

torch::Tensor TorchNet::forward(const NeuralGenerator &gen, std::span<const Point2> z,
                                std::span<const double> gamma, const torch::Tensor &base,
                                std::span<const Target *const> members) {
  const std::int64_t K = std::int64_t(z.size()), n = base.size(1);
  if (!graph) return mlp->forward(inputs(z, gamma, gen.gammaDimension())).reshape({K, n, 2});
  // Residuals in units of the point spacing, 1 / sqrt(N). Each stage sees
  // where the earlier ones put the points (as an input: no gradient flows
  // through the features), and its residual adds to theirs. An Owen base
  // brings each set's own neighbour graph; a rotated one shares `torus`, or
  // at another N the graph of that N's rotated base (the same for every z).
  std::vector<TorusGraph> graphs;
  torch::Tensor index = neighbours;
  if (gen.settings().base == BaseRandomization::Rotated && std::size_t(n) != torus.n) {
    const auto *p = reinterpret_cast<const Point2 *>(base[0].data_ptr<double>());
    graphs.push_back(buildTorusGraph(std::span(p, std::size_t(n)), torus.k));
    index = torch::from_blob(graphs[0].neighbours.data(),
                             {std::int64_t(graphs[0].neighbours.size())}, torch::kInt64)
                .clone();
  } else if (gen.settings().base == BaseRandomization::Owen) {
    // k is clamped to N - 1, so below the model's N it may be smaller.
    const std::int64_t k = std::int64_t(std::min<std::size_t>(torus.k, std::size_t(n) - 1));
    index = torch::empty({K, n * k}, torch::kInt64);
    for (std::int64_t set = 0; set < K; ++set) {
      const auto *p = reinterpret_cast<const Point2 *>(base[set].data_ptr<double>());
      graphs.push_back(buildTorusGraph(std::span(p, std::size_t(n)), torus.k));
      std::copy(graphs.back().neighbours.begin(), graphs.back().neighbours.end(),
                index[set].data_ptr<std::int64_t>());
    }
  }
  // The objectives whose gradients the points see: the generator's for a
  // single target, else one per distinct member (consecutive sets share
  // theirs), made once for all stages.
  std::vector<std::shared_ptr<const NonuniformL2asd>> made;
  std::vector<const NonuniformL2asd *> objectives;
  if (gen.settings().discrepancyGradient)
    for (std::size_t set = 0; set < std::size_t(K); ++set) {
      if (gen.gammaDimension() == 0) {
        objectives.push_back(objective.get());
      } else {
        if (set == 0 || members[set] != members[set - 1])
          made.push_back(std::make_shared<const NonuniformL2asd>(*members[set], kGradientGrid));
        objectives.push_back(made.back().get());
      }
    }
  torch::Tensor total;
  torch::Tensor current = base;
  for (int stage = 0; stage < gen.settings().stages; ++stage) {
    const auto [nodes, edges] = graphInputs(gen, gamma, current, graphs, members, objectives);
    torch::Tensor r = graph->forward(nodes, edges, index) * (1 / std::sqrt(double(n)));
    if (gen.settings().centred) r = r - r.mean(1, /*keepdim=*/true);
    total = stage == 0 ? r : total + r;
    if (stage + 1 < gen.settings().stages)
      current = (base + total.detach().to(torch::kFloat64)).contiguous();
  }
  return total;
}

torch::Tensor TorchNet::residuals(const torch::Tensor &v) const {
  // A few rows: matrix-vector products (dense_inference.h); more: LibTorch's
  // GEMM, which amortizes packing the weights over the rows.
  constexpr std::int64_t kRowsByVector = 4;
  FourierMlpImpl &m = *mlp.ptr();  // forward() is not const in LibTorch
  if (v.size(0) > kRowsByVector || m.B.scalar_type() != torch::kFloat32) return m.forward(v);
  const torch::Tensor e = m.encode(v).contiguous();
  std::vector<DenseLayer> layers;
  for (const torch::nn::Linear &l : {m.l1, m.l2, m.l3, m.l4, m.l5}) {
    if (!l->weight.is_contiguous() || !l->bias.is_contiguous()) return m.forward(v);
    layers.push_back({l->weight.data_ptr<float>(), l->bias.data_ptr<float>(),
                      int(l->weight.size(1)), int(l->weight.size(0))});
  }
  const std::int64_t outputs = m.l5->weight.size(0), width = e.size(1);
  torch::Tensor out = torch::empty({v.size(0), outputs}, torch::kFloat32);
  for (std::int64_t k = 0; k < v.size(0); ++k) {
    const std::vector<float> row =
        fourierMlpForward(layers, std::span(e[k].data_ptr<float>(), std::size_t(width)));
    std::copy(row.begin(), row.end(), out[k].data_ptr<float>());
  }
  return out;
}

torch::Tensor TorchNet::inputs(std::span<const Point2> z, std::span<const double> gamma,
                               std::size_t gammaDim) const {
  const std::int64_t K = std::int64_t(z.size()), cols = std::int64_t(2 + gammaDim);
  torch::Tensor v = torch::empty({K, cols}, torch::kFloat64);
  auto a = v.accessor<double, 2>();
  for (std::int64_t k = 0; k < K; ++k) {
    a[k][0] = z[k].x;
    a[k][1] = z[k].y;
    for (std::size_t g = 0; g < gammaDim; ++g) a[k][2 + g] = gamma[k * gammaDim + g];
  }
  return v.to(mlp->B.scalar_type());
}

torch::Tensor baseSets(const NeuralGenerator &gen, std::span<const Point2> z, std::size_t size) {
  const std::int64_t K = std::int64_t(z.size()),
                     n = std::int64_t(size == 0 ? gen.settings().n : size);
  torch::Tensor base = torch::empty({K, n, 2}, torch::kFloat64);
  for (std::int64_t k = 0; k < K; ++k)
    gen.baseSet(z[k], std::span<Point2>(reinterpret_cast<Point2 *>(base[k].data_ptr<double>()),
                                        std::size_t(n)));
  return base;
}

std::size_t TorchNet::parameterCount() const {
  std::size_t count = 0;
  for (const auto &p : module().parameters()) count += std::size_t(p.numel());
  return count;
}

std::vector<ModelTensor> TorchNet::tensors() const {
  std::vector<ModelTensor> out;
  auto add = [&](const std::string &name, const torch::Tensor &t) {
    const torch::Tensor f = t.detach().to(torch::kFloat32).contiguous();
    out.push_back({name, std::vector<std::int64_t>(f.sizes().begin(), f.sizes().end()),
                   std::vector<float>(f.data_ptr<float>(), f.data_ptr<float>() + f.numel())});
  };
  for (const auto &item : module().named_buffers()) add(item.key(), item.value());
  for (const auto &item : module().named_parameters()) add(item.key(), item.value());
  return out;
}

void TorchNet::loadWeights(const ModelFile &file, const std::string &path) {
  torch::NoGradGuard noGrad;
  auto fill = [&](const std::string &name, torch::Tensor &t) {
    const ModelTensor &mt = file.tensor(name, path);
    if (std::vector<std::int64_t>(t.sizes().begin(), t.sizes().end()) != mt.shape)
      throw std::runtime_error(path + ": tensor '" + name +
                               "' has the wrong shape for the network its metadata describes");
    t.copy_(torch::from_blob(const_cast<float *>(mt.data.data()), t.sizes(), torch::kFloat32));
  };
  for (auto &item : module().named_buffers()) fill(item.key(), item.value());
  for (auto &item : module().named_parameters()) fill(item.key(), item.value());
}

void TorchNet::rawPoints(const NeuralGenerator &gen, std::span<const Point2> z,
                         std::span<const double> gamma, std::size_t n,
                         std::span<const Target *const> members, std::span<Point2> out) const {
  torch::NoGradGuard noGrad;
  const std::int64_t K = std::int64_t(z.size());
  const torch::Tensor base = baseSets(gen, z, n);
  // forward() is not const in LibTorch; no weight changes here.
  TorchNet &self = const_cast<TorchNet &>(*this);
  const torch::Tensor r = gen.settings().arch == NetworkArch::Supplement
                              ? residuals(inputs(z, gamma, gen.gammaDimension()))
                              : self.forward(gen, z, gamma, base, members);
  const torch::Tensor residual =
      r.to(torch::kFloat64).reshape({K, std::int64_t(n), 2}).contiguous();
  const torch::Tensor points = (base + residual).contiguous();
  const auto *p = reinterpret_cast<const Point2 *>(points.data_ptr<double>());
  std::copy(p, p + K * std::int64_t(n), out.begin());
}

}  // namespace nuld
