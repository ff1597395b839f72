#include "sampler/neural/neural_generator.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "sampler/io/round_trip.h"
#include "sampler/neural/dense_inference.h"
#include "sampler/neural/model_file.h"
#include "sampler/neural/network.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"
#include "sampler/sequences/sobol.h"
#include "sampler/targets/target_spec.h"

namespace nuld {
namespace {

// The targets of consecutive sets: a family's target is rebuilt only when
// gamma changes (tabulating a Disney lobe costs milliseconds, and a bank
// generates hundreds of sets per gamma).
class FamilyTargets {
 public:
  explicit FamilyTargets(const TargetFamily &family) : family_(family) {}
  const Target &at(std::span<const double> gamma) {
    if (!target_ || !std::equal(gamma.begin(), gamma.end(), gamma_.begin(), gamma_.end())) {
      target_ = family_.target(gamma);
      gamma_.assign(gamma.begin(), gamma.end());
    }
    return *target_;
  }

 private:
  const TargetFamily &family_;
  std::vector<double> gamma_;
  std::shared_ptr<const Target> target_;
};

constexpr const char *kFormat = "nuld-neural-generator";
constexpr int kVersion = 1;
// The metadata 'base' of each randomization (files from before the Owen base
// all say the rotated one's).
constexpr const char *kRotatedBase = "sobol rotated by z";
constexpr const char *kOwenBase = "sobol owen-scrambled by a hash of z";

// B ~ N(0, sigma^2) from our own counter-based generator (Box-Muller), so a
// seed gives the same encoding on every machine and LibTorch version.
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

// The integer frequencies (a, b) of z with max(|a|, |b|) <= k, one of each
// +- pair (a > 0, or a = 0 and b > 0); gamma's columns are 0.
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

// The graph generator's input widths: per point the torus harmonics of u,
// the placed point x, three Jacobian features, log N, and gamma raw and
// Fourier-encoded; per edge the neighbour's offset in u and in x.
std::int64_t graphNodeFeatures(const NeuralSettings &s, std::size_t gammaDim) {
  const std::int64_t harmonics =
      ((2 * s.positionHarmonics + 1) * (2 * s.positionHarmonics + 1) - 1);
  return harmonics + 2 + 3 + 1 + std::int64_t(gammaDim) + (gammaDim > 0 ? s.encodingDims : 0) +
         (s.discrepancyGradient ? 3 : 0);
}
constexpr std::int64_t kGraphEdgeFeatures = 4;
// The grid of the L2 objective whose gradient --discrepancy-gradient feeds
// (exact on grid targets' own cells; 64^2 cells for closed-form ones).
constexpr int kGradientGrid = 64;

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

std::string joinSizes(const std::vector<std::size_t> &sizes) {
  std::string s;
  for (const std::size_t n : sizes) s += (s.empty() ? "" : ",") + std::to_string(n);
  return s;
}

}  // namespace

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

torch::nn::Module &NeuralGenerator::Net::module() {
  return graph ? static_cast<torch::nn::Module &>(*graph) : *mlp;
}

const torch::nn::Module &NeuralGenerator::Net::module() const {
  return graph ? static_cast<const torch::nn::Module &>(*graph) : *mlp;
}

torch::Tensor NeuralGenerator::Net::forward(const NeuralGenerator &gen, std::span<const Point2> z,
                                            std::span<const double> gamma,
                                            const torch::Tensor &base) {
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
  torch::Tensor total;
  torch::Tensor current = base;
  for (int stage = 0; stage < gen.settings().stages; ++stage) {
    const auto [nodes, edges] = graphInputs(gen, gamma, current, graphs);
    const torch::Tensor r = graph->forward(nodes, edges, index) * (1 / std::sqrt(double(n)));
    total = stage == 0 ? r : total + r;
    if (stage + 1 < gen.settings().stages)
      current = (base + total.detach().to(torch::kFloat64)).contiguous();
  }
  return total;
}

std::pair<torch::Tensor, torch::Tensor> NeuralGenerator::Net::graphInputs(
    const NeuralGenerator &gen, std::span<const double> gamma, const torch::Tensor &points,
    const std::vector<TorusGraph> &graphs) const {
  const NeuralSettings &s = gen.settings();
  const std::size_t K = std::size_t(points.size(0)), n = std::size_t(points.size(1)),
                    g = gen.gammaDimension();
  // One graph per set, one shared by all (a rotated base at another N), or `torus`.
  auto graphOf = [&](std::size_t set) -> const TorusGraph & {
    return graphs.empty() ? torus : graphs[graphs.size() == K ? set : 0];
  };
  const std::size_t k = graphOf(0).k;
  const std::int64_t F = graphNodeFeatures(s, g);
  const torch::Tensor harmonics = zHarmonicFrequencies(s.positionHarmonics, 2).to(torch::kFloat64);
  const std::int64_t H = harmonics.size(0);
  const double rootN = std::sqrt(double(n)), logN = std::log2(double(n)) / 10;
  const bool sphere = gen.domain() != Domain::Square;

  torch::Tensor nodes = torch::empty({std::int64_t(K), std::int64_t(n), F}, torch::kFloat64);
  torch::Tensor edges =
      torch::empty({std::int64_t(K), std::int64_t(n), std::int64_t(k), 4}, torch::kFloat64);
  const auto *pb = reinterpret_cast<const Point2 *>(points.data_ptr<double>());
  double *pn = nodes.data_ptr<double>();
  auto *pe = reinterpret_cast<Point2 *>(edges.data_ptr<double>());
  const auto hf = harmonics.accessor<double, 2>();
  std::vector<Point2> x(n), u(n), gradient(s.discrepancyGradient ? n : 0);
  std::vector<Jacobian2> jacobian(n);
  FamilyTargets targets(gen.family());
  for (std::size_t set = 0; set < K; ++set) {
    const std::vector<std::int64_t> &nb = graphOf(set).neighbours;
    const std::span<const double> gs = gamma.subspan(set * g, g);
    const Target *target = &targets.at(gs);
    std::vector<double> gammaCode;
    if (g > 0) {
      const torch::Tensor v =
          torch::from_blob(const_cast<double *>(gs.data()), {1, std::int64_t(g)}, torch::kFloat64);
      const torch::Tensor code = fourierFeatures(v, graph->B.to(torch::kFloat64)).contiguous();
      gammaCode.assign(code.data_ptr<double>(), code.data_ptr<double>() + code.numel());
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Point2 raw = pb[set * n + i];
      u[i] = {wrapUnit(raw.x), wrapUnit(raw.y)};
      x[i] = gen.place(raw, *target, &jacobian[i]);
    }
    // The descent direction: dL2^2/du (pulled back through T and balanced
    // per coordinate as the trainer does), over its root mean square.
    double gradientScale = 0;
    if (s.discrepancyGradient) {
      // One target: the objective built with the generator; a family: this
      // set's member.
      const auto objectiveHere =
          g == 0 ? objective : std::make_shared<const NonuniformL2asd>(*target, kGradientGrid);
      objectiveHere->squared(x, gradient);
      for (std::size_t i = 0; i < n; ++i) {
        gradient[i] = balancedPullback(jacobian[i].transposeTimes(gradient[i]), jacobian[i]);
        gradientScale +=
            (gradient[i].x * gradient[i].x + gradient[i].y * gradient[i].y) / double(n);
      }
      gradientScale = std::sqrt(gradientScale);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Jacobian2 &j = jacobian[i];
      double *f = pn + (set * n + i) * std::size_t(F);
      for (std::int64_t h = 0; h < H; ++h) {
        const double angle = 2 * std::numbers::pi * (hf[h][0] * u[i].x + hf[h][1] * u[i].y);
        *f++ = std::cos(angle);
        *f++ = std::sin(angle);
      }
      *f++ = 2 * x[i].x - 1;
      *f++ = 2 * x[i].y - 1;
      // How T stretches around u: the log lengths of J's columns and the
      // cosine between them (a zero or non-finite column reads as the floor).
      const double c0 = std::hypot(j.m[0][0], j.m[1][0]), c1 = std::hypot(j.m[0][1], j.m[1][1]);
      auto logLength = [](double c) {
        return c > 0 && std::isfinite(c) ? std::clamp(std::log(c), -8.0, 8.0) / 4 : -2.0;
      };
      *f++ = logLength(c0);
      *f++ = logLength(c1);
      const double dot = j.m[0][0] * j.m[0][1] + j.m[1][0] * j.m[1][1];
      *f++ = c0 > 0 && c1 > 0 && std::isfinite(dot / (c0 * c1)) ? dot / (c0 * c1) : 0.0;
      *f++ = logN;
      for (std::size_t q = 0; q < g; ++q) *f++ = 2 * gs[q] - 1;
      for (const double c : gammaCode) *f++ = c;
      if (s.discrepancyGradient) {
        const bool usable = gradientScale > 0 && std::isfinite(gradientScale);
        *f++ = usable ? gradient[i].x / gradientScale : 0.0;
        *f++ = usable ? gradient[i].y / gradientScale : 0.0;
        *f++ = usable
                   ? std::clamp(std::log(gradientScale * double(n) * double(n)), -20.0, 20.0) / 10
                   : -2.0;
      }
    }
    // Edges: the neighbour's offset on the torus of u (for the base set the
    // same for every z) and in x, both in units of the spacing; x's is
    // clamped, as a neighbour across the square's seam or a stretched
    // region is simply far.
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t e = 0; e < k; ++e) {
        const std::size_t j = std::size_t(nb[i * k + e]);
        const Point2 du = torusDifference(u[i], u[j]);
        Point2 dx = x[j] - x[i];
        if (sphere) dx.x -= std::floor(dx.x + 0.5);  // longitude is periodic
        auto clampSpacing = [&](double d) { return std::clamp(d * rootN, -4.0, 4.0); };
        Point2 *edge = pe + 2 * ((set * n + i) * k + e);
        edge[0] = rootN * du;
        edge[1] = {clampSpacing(dx.x), clampSpacing(dx.y)};
      }
  }
  const auto dtype = graph->embed->weight.scalar_type();
  return {nodes.to(dtype), edges.to(dtype)};
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

void NeuralSettings::validate() const {
  auto bad = [](const std::string &what) { throw std::invalid_argument("neural: " + what); };
  if (n < 1 || n > (std::size_t(1) << 20)) bad("n must be in [1, 2^20]");
  if (hidden < 1 || hidden > 16384) bad("hidden width must be in [1, 16384]");
  if (!(sigma > 0 && std::isfinite(sigma))) bad("sigma must be positive");
  if (encodingDims < 2 || encodingDims % 2 != 0) bad("the encoding size must be even and >= 2");
  if (zHarmonics < 0 || zHarmonics > 32) bad("z harmonics must be in [0, 32]");
  if (!(offsetRange > 0 && offsetRange <= 1)) bad("the offset range must be in (0, 1]");
  if (!trainingNs.empty()) {
    if (arch != NetworkArch::Graph)
      bad("several training sizes need the graph generator (the supplement's network emits a "
          "fixed N)");
    if (trainingNs.size() > 64) bad("at most 64 training sizes");
    for (const std::size_t m : trainingNs)
      if (m < 1 || m > (std::size_t(1) << 20)) bad("training sizes must be in [1, 2^20]");
    if (trainingNs.front() != n) bad("n must be the first training size");
  }
  if (arch == NetworkArch::Graph) {
    if (zHarmonics != 0) bad("z harmonics belong to the supplement's network, not the graph one");
    if (neighbours < 1 || neighbours > 64) bad("neighbours must be in [1, 64]");
    if (rounds < 0 || rounds > 16) bad("rounds must be in [0, 16]");
    if (positionHarmonics < 1 || positionHarmonics > 16)
      bad("position harmonics must be in [1, 16]");
    if (stages < 1 || stages > 16) bad("stages must be in [1, 16]");
    if (base == BaseRandomization::Owen && offsetRange != 1)
      bad("the offset range applies to the rotated base only");
  } else if (base != BaseRandomization::Rotated) {
    bad("the supplement's network needs the rotated base (its residuals are functions of z)");
  }
}

std::vector<std::size_t> NeuralSettings::sizesTrained() const {
  return trainingNs.empty() ? std::vector<std::size_t>{n} : trainingNs;
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
                               std::size_t n, std::span<Point2> out) const {
  const std::size_t K = z.size(), g = gammaDimension();
  checkSize(n);
  if (gamma.size() != K * g || out.size() != K * n)
    throw std::invalid_argument("neural: generate() sizes do not match K sets");
  for (std::size_t k = 0; k < K; ++k) checkGamma(*family_, gamma.subspan(k * g, g));
  if (K == 0) return;
  torch::NoGradGuard noGrad;
  const torch::Tensor base = baseSets(*this, z, n);
  const torch::Tensor r = settings_.arch == NetworkArch::Supplement
                              ? net_->residuals(net_->inputs(z, gamma, g))
                              : net_->forward(*this, z, gamma, base);
  const torch::Tensor residual =
      r.to(torch::kFloat64).reshape({std::int64_t(K), std::int64_t(n), 2}).contiguous();
  const torch::Tensor points = (base + residual).contiguous();
  const auto *p = reinterpret_cast<const Point2 *>(points.data_ptr<double>());
  FamilyTargets targets(*family_);
  for (std::size_t k = 0; k < K; ++k) {
    const Target *target = &targets.at(gamma.subspan(k * g, g));
    for (std::size_t i = k * n; i < (k + 1) * n; ++i) {
      if (!isFinite(p[i]))
        throw std::runtime_error("neural: the network produced a non-finite point");
      out[i] = place(p[i], *target);
    }
  }
}

PointSet NeuralGenerator::generateSets(std::size_t instances, std::uint64_t seed,
                                       std::span<const double> gamma, std::size_t n) const {
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
  generate(z, gammas, n, set.points);
  return set;
}

std::map<std::string, std::string> NeuralGenerator::metadata() const {
  std::map<std::string, std::string> m = {
      {"format", kFormat},
      {"arch", toString(settings_.arch)},
      {"version", std::to_string(kVersion)},
      {"n", std::to_string(settings_.n)},
      {"dimension", "2"},
      {"domain", toString(domain())},
      {"family", settings_.family},
      {"gamma_dimension", std::to_string(gammaDimension())},
      {"hidden", std::to_string(settings_.hidden)},
      {"sigma", formatRoundTrip(settings_.sigma)},
      {"encoding_dims", std::to_string(settings_.encodingDims)},
      {"z_harmonics", std::to_string(settings_.zHarmonics)},
      {"offset_range", formatRoundTrip(settings_.offsetRange)},
      {"seed", std::to_string(settings_.seed)},
      {"base", settings_.base == BaseRandomization::Owen ? kOwenBase : kRotatedBase},
      {"mapping", settings_.mapped ? "mapped" : "unmapped"}};
  if (settings_.arch == NetworkArch::Graph) {
    m["neighbours"] = std::to_string(settings_.neighbours);
    m["rounds"] = std::to_string(settings_.rounds);
    m["position_harmonics"] = std::to_string(settings_.positionHarmonics);
    m["stages"] = std::to_string(settings_.stages);
    m["discrepancy_gradient"] = settings_.discrepancyGradient ? "1" : "0";
  }
  // Only for several sizes, so single-size files keep their metadata.
  if (!settings_.trainingNs.empty()) m["training_n"] = joinSizes(settings_.trainingNs);
  return m;
}

ModelFile NeuralGenerator::toModelFile(const std::map<std::string, std::string> &extra) const {
  ModelFile file;
  file.metadata = extra;
  for (const auto &[k, v] : metadata()) file.metadata[k] = v;
  auto add = [&](const std::string &name, const torch::Tensor &t) {
    const torch::Tensor f = t.detach().to(torch::kFloat32).contiguous();
    file.tensors.push_back(
        {name, std::vector<std::int64_t>(f.sizes().begin(), f.sizes().end()),
         std::vector<float>(f.data_ptr<float>(), f.data_ptr<float>() + f.numel())});
  };
  for (const auto &item : net_->module().named_buffers()) add(item.key(), item.value());
  for (const auto &item : net_->module().named_parameters()) add(item.key(), item.value());
  return file;
}

void NeuralGenerator::save(const std::string &path,
                           const std::map<std::string, std::string> &extra) const {
  writeModelFile(path, toModelFile(extra));
}

void NeuralGenerator::loadWeights(const ModelFile &file, const std::string &path) {
  torch::NoGradGuard noGrad;
  auto fill = [&](const std::string &name, torch::Tensor &t) {
    const ModelTensor &mt = file.tensor(name, path);
    if (std::vector<std::int64_t>(t.sizes().begin(), t.sizes().end()) != mt.shape)
      throw std::runtime_error(path + ": tensor '" + name +
                               "' has the wrong shape for the network its metadata describes");
    t.copy_(torch::from_blob(const_cast<float *>(mt.data.data()), t.sizes(), torch::kFloat32));
  };
  for (auto &item : net_->module().named_buffers()) fill(item.key(), item.value());
  for (auto &item : net_->module().named_parameters()) fill(item.key(), item.value());
}

NeuralGenerator NeuralGenerator::load(const std::string &path) {
  const ModelFile file = readModelFile(path);
  if (file.metadata.count("format") == 0 || file.metadata.at("format") != kFormat)
    throw std::runtime_error(path + ": not a neural generator model (metadata 'format' is not '" +
                             kFormat + "')");
  if (file.value("version", path) != std::to_string(kVersion))
    throw std::runtime_error(path + ": model version " + file.value("version", path) +
                             ", this program reads version " + std::to_string(kVersion));
  auto number = [&](const std::string &key) {
    const std::string &v = file.value(key, path);
    try {
      std::size_t used = 0;
      const double x = std::stod(v, &used);
      if (used != v.size()) throw std::invalid_argument(v);
      return x;
    } catch (const std::exception &) {
      throw std::runtime_error(path + ": model metadata '" + key + "' is not a number: '" + v +
                               "'");
    }
  };
  NeuralSettings s;
  // Files from before the graph generator have no 'arch': the supplement's.
  if (file.metadata.count("arch")) {
    try {
      s.arch = parseNetworkArch(file.metadata.at("arch"));
    } catch (const std::invalid_argument &e) {
      throw std::runtime_error(path + ": model metadata 'arch': " + e.what());
    }
  }
  if (s.arch == NetworkArch::Graph) {
    s.neighbours = int(number("neighbours"));
    s.rounds = int(number("rounds"));
    s.positionHarmonics = int(number("position_harmonics"));
    s.stages = int(number("stages"));
    s.discrepancyGradient = number("discrepancy_gradient") != 0;
    if (file.metadata.count("training_n")) {
      try {
        s.trainingNs = parseSizeList("model metadata 'training_n'", file.metadata.at("training_n"));
      } catch (const std::invalid_argument &e) {
        throw std::runtime_error(path + ": " + e.what());
      }
    }
  }
  if (file.metadata.count("base")) {
    const std::string &base = file.metadata.at("base");
    if (base == kOwenBase)
      s.base = BaseRandomization::Owen;
    else if (base != kRotatedBase)
      throw std::runtime_error(path + ": model metadata 'base' is '" + base + "', expected '" +
                               kRotatedBase + "' or '" + kOwenBase + "'");
  }
  s.n = std::size_t(number("n"));
  s.hidden = int(number("hidden"));
  s.sigma = number("sigma");
  s.encodingDims = int(number("encoding_dims"));
  // Files from before these options have no keys: no harmonics, full range.
  if (file.metadata.count("z_harmonics")) s.zHarmonics = int(number("z_harmonics"));
  if (file.metadata.count("offset_range")) s.offsetRange = number("offset_range");
  try {
    s.seed = std::stoull(file.value("seed", path));
  } catch (const std::logic_error &) {
    throw std::runtime_error(path + ": model metadata 'seed' is not an unsigned integer");
  }
  s.family = file.value("family", path);
  const std::string &mapping = file.value("mapping", path);
  if (mapping != "mapped" && mapping != "unmapped")
    throw std::runtime_error(path + ": model metadata 'mapping' is '" + mapping +
                             "', expected mapped or unmapped");
  s.mapped = mapping == "mapped";
  try {
    NeuralGenerator gen(std::move(s));
    gen.loadWeights(file, path);
    gen.fileMetadata_ = file.metadata;
    return gen;
  } catch (const std::invalid_argument &e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace nuld
