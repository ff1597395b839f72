#include "sampler/neural/neural_generator.h"

// The generator: its settings, the base sets, and where the points its
// network (torch_net.cpp, in the LibTorch plugin) moves them land. The model
// files are in neural_generator_file.cpp.

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "sampler/io/round_trip.h"
#include "sampler/neural/neural_runtime.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"
#include "sampler/sequences/sobol.h"

namespace nuld {

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

NeuralGenerator::NeuralGenerator(const NeuralSettings &settings)
    : NeuralGenerator(settings, NetworkLoad::Now) {}

NeuralGenerator::NeuralGenerator(const NeuralSettings &settings, NetworkLoad when)
    : settings_(settings) {
  settings_.validate();
  family_ = makeTargetFamily(settings_.family);
  settings_.family = family_->spec();
  if (settings_.mapped && gammaDimension() == 0 && !family_->target({})->hasInverse())
    throw std::invalid_argument("neural: target '" + settings_.family +
                                "' has no inverse CDF; train it unmapped");
  sobol_.resize(settings_.n);
  for (std::size_t i = 0; i < settings_.n; ++i) sobol_[i] = {sobolSample(i, 0), sobolSample(i, 1)};
  if (when == NetworkLoad::Now) network();
}

NeuralNet &NeuralGenerator::network() const {
  const std::lock_guard guard(*netLock_);
  if (!net_) {
    // Built whole before it is kept: weights that do not fit leave no
    // half-loaded network behind.
    std::unique_ptr<NeuralNet> net = neuralRuntime().makeNet(*this, sobol_);
    if (pendingWeights_) net->loadWeights(*pendingWeights_, path_);
    net_ = std::move(net);
    pendingWeights_.reset();
  }
  return *net_;
}

NeuralGenerator::NeuralGenerator(NeuralGenerator &&) noexcept = default;
NeuralGenerator &NeuralGenerator::operator=(NeuralGenerator &&) noexcept = default;
NeuralGenerator::~NeuralGenerator() = default;

std::size_t NeuralGenerator::parameterCount() const { return network().parameterCount(); }

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
  std::vector<Point2> raw(K * n);
  network().rawPoints(*this, z, gamma, n, members, raw);
  const Point2 *p = raw.data();
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
