#include "sampler/neural/neural_generator.h"

// The generator: its settings, the network it builds, the base sets and the
// residuals it adds to them. The graph generator's inputs are in
// graph_inputs.cpp, the model files in neural_generator_file.cpp.

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "sampler/io/round_trip.h"
#include "sampler/neural/dense_inference.h"
#include "sampler/neural/network.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"
#include "sampler/sequences/sobol.h"

namespace nuld {
namespace {

std::unique_ptr<NeuralGenerator::Net> makeNet(const NeuralSettings &s, std::size_t gammaDim,
                                              std::span<const Point2> base) {
  auto net = std::make_unique<NeuralGenerator::Net>();
  torch::manual_seed(s.seed);  // LibTorch's default initialization of the hidden layers
  if (s.arch == NetworkArch::Graph) {
    const torch::Tensor B = drawFrequencies(s.encodingDims / 2, int(gammaDim), s.sigma, s.seed);
    net->graph =
        GraphNet(B, graphNodeFeatures(s, gammaDim), kGraphEdgeFeatures, s.hidden, s.rounds);
    net->torus = buildTorusGraph(base, std::size_t(s.neighbours));
    const std::int64_t n = std::int64_t(s.n), k = std::int64_t(net->torus.k);
    net->neighbours =
        torch::from_blob(net->torus.neighbours.data(), {n * k}, torch::kInt64).clone();
    return net;
  }
  torch::Tensor B = drawFrequencies(s.encodingDims / 2, int(2 + gammaDim), s.sigma, s.seed);
  if (s.zHarmonics > 0) B = torch::cat({B, zHarmonicFrequencies(s.zHarmonics, int(2 + gammaDim))});
  net->mlp = FourierMlp(B, s.hidden, std::int64_t(2 * s.n));
  return net;
}

}  // namespace

torch::nn::Module &NeuralGenerator::Net::module() {
  return graph ? static_cast<torch::nn::Module &>(*graph) : *mlp;
}

const torch::nn::Module &NeuralGenerator::Net::module() const {
  return graph ? static_cast<const torch::nn::Module &>(*graph) : *mlp;
}

torch::Tensor NeuralGenerator::Net::forward(const NeuralGenerator &gen, std::span<const Point2> z,
                                            std::span<const double> gamma,
                                            const torch::Tensor &base,
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

torch::Tensor NeuralGenerator::Net::residuals(const torch::Tensor &v) const {
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

torch::Tensor NeuralGenerator::Net::inputs(std::span<const Point2> z, std::span<const double> gamma,
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

Point2 balancedPullback(Point2 pulled, const Jacobian2 &j) {
  auto scaled = [](double component, double a, double b) {
    const double length = std::hypot(a, b);
    return length > 0 && std::isfinite(length) ? component / length : 0.0;
  };
  return {scaled(pulled.x, j.m[0][0], j.m[1][0]), scaled(pulled.y, j.m[0][1], j.m[1][1])};
}

Point2 NeuralGenerator::place(Point2 raw, const Target &target, Jacobian2 *jacobian) const {
  if (settings_.mapped) {
    // u wraps around the square like the Cranley-Patterson base set itself.
    const Inversion inv = target.invert({wrapUnit(raw.x), wrapUnit(raw.y)});
    if (jacobian) *jacobian = inv.jacobian;
    return inv.x;
  }
  double sign = 1;
  const Point2 p = wrapToDomain(raw, domain(), &sign);
  if (jacobian) *jacobian = Jacobian2{{{1, 0}, {0, sign}}};
  return p;
}

NeuralGenerator::NeuralGenerator(const NeuralSettings &settings) : settings_(settings) {
  settings_.validate();
  family_ = makeTargetFamily(settings_.family);
  settings_.family = family_->spec();
  if (settings_.mapped && gammaDimension() == 0 && !family_->target({})->hasInverse())
    throw std::invalid_argument("neural: target '" + settings_.family +
                                "' has no inverse CDF; train it unmapped");
  sobol_.resize(settings_.n);
  for (std::size_t i = 0; i < settings_.n; ++i) sobol_[i] = {sobolSample(i, 0), sobolSample(i, 1)};
  net_ = makeNet(settings_, family_->gammaDimension(), sobol_);
  if (settings_.arch == NetworkArch::Graph && settings_.discrepancyGradient &&
      gammaDimension() == 0)
    net_->objective = std::make_shared<const NonuniformL2asd>(*family_->target({}), kGradientGrid);
}

NeuralGenerator::NeuralGenerator(NeuralGenerator &&) noexcept = default;
NeuralGenerator &NeuralGenerator::operator=(NeuralGenerator &&) noexcept = default;
NeuralGenerator::~NeuralGenerator() = default;

std::size_t NeuralGenerator::parameterCount() const {
  std::size_t count = 0;
  for (const auto &p : net_->module().parameters()) count += std::size_t(p.numel());
  return count;
}

void NeuralGenerator::checkSize(std::size_t n) const {
  if (n < 1 || n > (std::size_t(1) << 20))
    throw std::invalid_argument("neural: sets of " + std::to_string(n) +
                                " points: expected N in [1, 2^20]");
  if (!anySize() && n != settings_.n)
    throw std::invalid_argument("neural: the supplement's network makes sets of " +
                                std::to_string(settings_.n) + " points only, not " +
                                std::to_string(n));
}

void NeuralGenerator::baseSet(Point2 z, std::span<Point2> out) const {
  checkSize(out.size());
  if (settings_.base == BaseRandomization::Owen) {
    // Distinct offsets give unrelated scramblings; the model's seed keys them.
    const std::uint64_t seed =
        hash3(settings_.seed, std::bit_cast<std::uint64_t>(z.x), std::bit_cast<std::uint64_t>(z.y));
    generateSet({SequenceKind::Sobol, Scramble::Owen, seed}, 0, out);
    return;
  }
  const bool square = domain() == Domain::Square;
  const Point2 offset{settings_.offsetRange * z.x, settings_.offsetRange * z.y};
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Point2 s = i < sobol_.size() ? sobol_[i] : Point2{sobolSample(i, 0), sobolSample(i, 1)};
    const Point2 p = s + offset;
    // The rotation wraps around the square (Cranley-Patterson).
    out[i] = square ? Point2{wrapUnit(p.x), wrapUnit(p.y)} : p;
  }
}

std::string NeuralGenerator::notRandomizedReason() const {
  if (settings_.offsetRange >= 1) return "";
  const std::string r = formatRoundTrip(settings_.offsetRange);
  return "trained with --offset-range " + r +
         " (a diagnostic): its base set moves by offsets in [0, " + r +
         ")^2 only, so its sets are not randomized over the torus";
}

void NeuralGenerator::generate(std::span<const Point2> z, std::span<const double> gamma,
                               std::span<Point2> out) const {
  generate(z, gamma, settings_.n, out);
}

void NeuralGenerator::generate(std::span<const Point2> z, std::span<const double> gamma,
                               std::size_t n, std::span<Point2> out, const Target *member,
                               std::span<const double> memberGamma) const {
  const std::size_t K = z.size(), g = gammaDimension();
  checkSize(n);
  if (gamma.size() != K * g || out.size() != K * n)
    throw std::invalid_argument("neural: generate() sizes do not match K sets");
  for (std::size_t k = 0; k < K; ++k) checkGamma(*family_, gamma.subspan(k * g, g));
  if (K == 0) return;
  torch::NoGradGuard noGrad;
  // Each set's member of the family: the caller's where given, else built
  // once per run of sets with the same gamma (tabulating a Disney lobe costs
  // milliseconds, and a bank has many sets per gamma) and kept alive for
  // the whole call.
  std::vector<std::shared_ptr<const Target>> built;
  std::vector<const Target *> members(K);
  for (std::size_t k = 0; k < K; ++k) {
    const std::span<const double> gk = gamma.subspan(k * g, g);
    if (member && std::ranges::equal(gk, memberGamma)) {
      members[k] = member;
    } else if (k > 0 && std::ranges::equal(gk, gamma.subspan((k - 1) * g, g))) {
      members[k] = members[k - 1];
    } else {
      built.push_back(family_->target(gk));
      members[k] = built.back().get();
    }
  }
  const torch::Tensor base = baseSets(*this, z, n);
  const torch::Tensor r = settings_.arch == NetworkArch::Supplement
                              ? net_->residuals(net_->inputs(z, gamma, g))
                              : net_->forward(*this, z, gamma, base, members);
  const torch::Tensor residual =
      r.to(torch::kFloat64).reshape({std::int64_t(K), std::int64_t(n), 2}).contiguous();
  const torch::Tensor points = (base + residual).contiguous();
  const auto *p = reinterpret_cast<const Point2 *>(points.data_ptr<double>());
  for (std::size_t k = 0; k < K; ++k)
    for (std::size_t i = k * n; i < (k + 1) * n; ++i) {
      if (!isFinite(p[i]))
        throw std::runtime_error("neural: the network produced a non-finite point");
      out[i] = place(p[i], *members[k]);
    }
}

PointSet NeuralGenerator::generateSets(std::size_t instances, std::uint64_t seed,
                                       std::span<const double> gamma, std::size_t n,
                                       const Target *member) const {
  if (n == 0) n = settings_.n;
  std::vector<Point2> z(instances);
  Rng rng(seed, 0x2);
  for (Point2 &zk : z) zk = {rng.uniform(), rng.uniform()};
  std::vector<double> gammas;
  for (std::size_t k = 0; k < instances; ++k)
    gammas.insert(gammas.end(), gamma.begin(), gamma.end());
  PointSet set;
  set.n = n;
  set.points.resize(instances * n);
  generate(z, gammas, n, set.points, member, gamma);
  return set;
}

}  // namespace nuld
