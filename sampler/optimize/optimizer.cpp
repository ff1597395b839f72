#include "sampler/optimize/optimizer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sampler/io/atomic_file.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/io/round_trip.h"
#include "sampler/loss/box_mass.h"
#include "sampler/loss/soft_box_loss.h"
#include "sampler/metrics/discrepancy.h"
#include "sampler/optimize/adam.h"
#include "sampler/optimize/schedule.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/grid_target.h"
#include "sampler/targets/target_spec.h"

namespace nuld {
namespace {
// Points per task in the per-point steps (inverse CDF, Adam): enough to
// outweigh a task's cost, few enough that 2048 points use two cores.
constexpr std::size_t kPointBlock = 512;
}  // namespace

std::string OptimizerSettings::describe() const {
  const auto r = [](double v) { return formatRoundTrip(v); };
  std::ostringstream s;
  s << "preset=" << preset << " n=" << n << " instances=" << instances << " epochs=" << epochs
    << " boxes=" << boxes << " box_kind=" << toString(boxKind)
    << " mass=" << (mcSamples ? "mc:" + std::to_string(mcSamples) : std::string("exact"))
    << " mapping=" << toString(mapping) << " objective=" << toString(objective)
    << " lr=" << r(lrStart) << ".." << r(lrEnd) << " alpha=" << r(alphaStart) << ".." << r(alphaEnd)
    << " ramp=" << r(rampFraction) << " cutoff=" << r(cutoff) << " seed=" << seed;
  // Only when on, so that the sets and checkpoints made before the term
  // existed keep their fingerprints.
  if (unionWeight > 0) s << " union=" << r(unionWeight) << "/" << unionGroupSize();
  if (firstInstance > 0) s << " first_instance=" << firstInstance;
  if (!nestedSizes.empty()) {
    s << " nested=";
    for (std::size_t i = 0; i < nestedSizes.size(); ++i) s << (i ? "," : "") << nestedSizes[i];
    s << "^" << r(nestedPower);
  }
  return s.str();
}

std::vector<std::size_t> OptimizerSettings::prefixSizes() const {
  std::vector<std::size_t> sizes = nestedSizes;
  sizes.push_back(n);
  return sizes;
}

std::vector<std::size_t> nestedChain(std::size_t from, std::size_t n) {
  std::vector<std::size_t> sizes;
  for (std::size_t m = std::max<std::size_t>(from, 1); m < n; m *= 2) sizes.push_back(m);
  return sizes;
}

void OptimizerSettings::validate() const {
  auto bad = [](const std::string &what) { throw std::invalid_argument("optimizer: " + what); };
  if (n < 1) bad("n must be >= 1");
  if (instances < 1) bad("instances must be >= 1");
  if (epochs < 1) bad("epochs must be >= 1");
  if (objective == Objective::SoftBoxes && boxes < 1) bad("boxes must be >= 1");
  if (!(lrStart > 0 && lrEnd > 0) || !std::isfinite(lrStart) || !std::isfinite(lrEnd))
    bad("learning rates must be finite and > 0");
  if (!(alphaStart > 0 && alphaEnd > 0) || !std::isfinite(alphaStart) || !std::isfinite(alphaEnd))
    bad("alpha must be finite and > 0");
  // Beyond this the sigmoid is a hard box edge: no gradient reaches a point.
  if (alphaStart > 1e7 || alphaEnd > 1e7) bad("alpha must be at most 1e7");
  if (!(rampFraction >= 0 && rampFraction <= 1)) bad("ramp fraction must lie in [0, 1]");
  if (!(cutoff > 0)) bad("cutoff must be > 0");
  if (!(unionWeight >= 0) || !std::isfinite(unionWeight))
    bad("union weight must be finite and >= 0");
  if (unionWeight > 0 && unionGroup == 1) bad("union group must hold >= 2 instances");
  if (unionWeight > 0 && instances < 2) bad("the union term needs >= 2 instances");
  if (unionWeight > 0 && objective != Objective::ExactL2asd)
    bad("the union term is defined for the l2asd objective only");
  for (std::size_t i = 0; i < nestedSizes.size(); ++i)
    if (nestedSizes[i] < 1 || nestedSizes[i] >= n ||
        (i > 0 && nestedSizes[i] <= nestedSizes[i - 1]))
      bad("nested prefix sizes must ascend, each >= 1 and below n = " + std::to_string(n));
  if (!(nestedPower >= 0) || !std::isfinite(nestedPower))
    bad("the nested prefixes' weight power must be finite and >= 0");
  if (unionWeight > 0 && firstInstance > 0)
    bad("the union term couples all instances: they cannot be optimized in parts");
}

OptimizerSettings presetSettings(const std::string &name, std::size_t n) {
  OptimizerSettings s;
  s.preset = name;
  s.n = n;
  const bool large = n >= 2048;
  if (name == "uniform") {
    s.epochs = 2000;
    s.boxes = large ? 32768 : 8192;
    s.lrStart = large ? 1e-4 : 1e-3;
    s.alphaEnd = large ? 6000 : 2000;
  } else if (name == "nonuniform" || name == "nonuniform-mc") {
    s.epochs = 1000;
    s.lrStart = 1e-4;
    s.alphaEnd = large ? 6000 : 2000;
    s.boxes = large ? 32768 : 8192;
    if (name == "nonuniform-mc") {
      s.mcSamples = std::size_t(1) << 17;
      if (!large) s.boxes = 4096;
    }
  } else if (name == "sphere" || name == "sphere-mc") {
    s.epochs = 5000;
    // The supplement's 16384 boxes are for its 2048 points. Sets of up to 64
    // points end as good with 2048 boxes, 4 to 8 times faster (measured at
    // N = 4, 16 and 64 over 4 seeds: tools/experiments/optimizer_speed.md,
    // "Boxes for small sets"); the Monte Carlo variant stays the paper's.
    s.boxes = name == "sphere" && n <= 64 ? 2048 : 16384;
    s.lrStart = 1e-4;
    s.alphaEnd = 6000;
    if (name == "sphere-mc") s.mcSamples = 65536;
  } else if (name == "sphere-exact") {
    // The exact L2asd with the bank term, from Owen-Sobol. Its gradient has
    // no sampled boxes, so it takes steps far larger than the soft preset's
    // and needs a tenth of its epochs; on the environment maps these sets
    // render at least as well in a small part of the time
    // (tools/experiments/environment_sets_setup.md, "Environment sets in
    // seconds: the exact objective", has the schedule sweep and the figures).
    s.epochs = 500;
    s.objective = Objective::ExactL2asd;
    s.unionWeight = 3;
    s.lrStart = 1e-2;
    s.lrEnd = 1e-5;
  } else {
    throw std::invalid_argument(
        "unknown preset '" + name +
        "' (expected uniform, nonuniform, nonuniform-mc, sphere, sphere-mc or sphere-exact)");
  }
  return s;  // the rest as OptimizerSettings' defaults (lr end 1e-7, alpha from 20)
}

std::string defaultPreset(const Target &target) {
  if (target.domain() != Domain::Square) return "sphere";
  return target.isUniform() ? "uniform" : "nonuniform";
}

DirectOptimizer::DirectOptimizer(const Target &target, OptimizerSettings settings)
    : target_(target), settings_(std::move(settings)) {
  settings_.validate();
  if (settings_.mapping == Mapping::Mapped && !target.hasInverse())
    throw std::invalid_argument("optimizer: target '" + target.spec() +
                                "' has no inverse CDF; use --mapping clamp or toroidal");
  if (settings_.objective == Objective::ExactL2asd) {
    if (!target.isUniform() && !dynamic_cast<const GridTarget *>(&target))
      throw std::invalid_argument(
          "optimizer: the exact l2asd objective needs a uniform or a grid (image, envmap) target; "
          "'" +
          target.spec() + "' is neither");
    // Exact for both: the uniform CDF ab is bilinear on a single cell, and a
    // grid target's CDF is bilinear on its own cells.
    exactObjective_ = std::make_shared<NonuniformL2asd>(target, 1);
  }
  if (settings_.objective == Objective::PeriodicL2) {
    if (!target.isUniform())
      throw std::invalid_argument(
          "optimizer: the l2per objective optimizes uniform sets on the torus; target '" +
          target.spec() + "' is not uniform (optimize --target uniform, then nuld map --shifts)");
    if (settings_.mapping != Mapping::Toroidal)
      throw std::invalid_argument(
          "optimizer: the l2per objective needs --mapping toroidal (the points live on the "
          "torus)");
  }
}

OptimizerState DirectOptimizer::initialState() const {
  const std::size_t n = settings_.n, K = settings_.instances;
  OptimizerState s;
  const SequenceOptions sobol{SequenceKind::Sobol, Scramble::Owen, settings_.seed};
  PointSet init;
  init.points.resize(n * K);
  for (std::size_t k = 0; k < K; ++k)
    generatePoints(sobol, std::uint32_t(settings_.firstInstance + k),
                   std::span(init.points).subspan(k * n, n));
  // Unmapped optimization starts from the same uniform points: it is the
  // variant for targets without an inverse CDF, and the supplement's Fig. 3
  // compares it with mapping on exactly that footing.
  s.params = init.points;
  s.m.assign(n * K, Point2{});
  s.v.assign(n * K, Point2{});
  s.lastLoss.assign(K, 0.0);
  return s;
}

void DirectOptimizer::run(OptimizerState &state, int untilEpoch,
                          const std::function<void(const EpochReport &)> &progress) const {
  const OptimizerSettings &s = settings_;
  const std::size_t n = s.n, K = s.instances;
  if (state.params.size() != n * K || state.m.size() != n * K || state.v.size() != n * K)
    throw std::invalid_argument("optimizer: state does not match the settings");
  state.lastLoss.resize(K, 0.0);
  untilEpoch = std::min(untilEpoch, s.epochs);
  const bool mapped = s.mapping == Mapping::Mapped && !target_.isUniform();
  std::vector<Point2> x(n * K), grad(n * K);
  std::vector<Jacobian2> jac(mapped ? n * K : 0);
  const auto slice = [n](auto &v, std::size_t k) {
    return v.empty() ? std::span(v.data(), 0) : std::span(v).subspan(k * n, n);
  };
  for (int epoch = state.epoch; epoch < untilEpoch; ++epoch) {
    const double lr = logLinear(s.lrStart, s.lrEnd, epoch, s.epochs);
    // Instances are independent but for the bank term: run them side by
    // side (the loss kernel is parallel inside too; TBB balances the two).
    tbb::parallel_for(std::size_t(0), K, [&](std::size_t k) {
      mapToTarget(slice(state.params, k), slice(x, k), slice(jac, k));
      state.lastLoss[k] = instanceLoss(k, epoch, slice(x, k), slice(grad, k));
    });
    const double bankLoss = s.unionWeight > 0 ? unionLoss(epoch, x, grad) : 0.0;
    // A learning rate far too large shows first as a non-finite loss; stop
    // there rather than carry NaN into the points.
    for (double l : state.lastLoss)
      if (!std::isfinite(l) || !std::isfinite(bankLoss))
        throw std::runtime_error("optimizer: the loss became non-finite at epoch " +
                                 std::to_string(epoch + 1) + " (learning rate " +
                                 formatRoundTrip(lr) + "): the optimization diverged; lower --lr");
    // Point by point, so blocks of any instance can run side by side.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n * K, kPointBlock), [&](const auto &r) {
      const auto part = [&](auto &v) { return std::span(v).subspan(r.begin(), r.size()); };
      const auto g = part(grad);
      if (mapped)
        for (std::size_t i = 0; i < g.size(); ++i) g[i] = jac[r.begin() + i].transposeTimes(g[i]);
      const auto params = part(state.params);
      adamStep(params, g, part(state.m), part(state.v), epoch + 1, lr);
      constrain(params);
    });
    state.epoch = epoch + 1;
    if (progress) {
      EpochReport r;
      r.epoch = epoch + 1;
      r.epochs = s.epochs;
      for (double l : state.lastLoss) r.loss += l / double(K);
      r.unionLoss = bankLoss;
      r.alpha = s.objective == Objective::SoftBoxes
                    ? linearRamp(s.alphaStart, s.alphaEnd, s.rampFraction, epoch, s.epochs)
                    : 0.0;
      r.lr = lr;
      progress(r);
    }
  }
}

void DirectOptimizer::mapToTarget(std::span<const Point2> params, std::span<Point2> x,
                                  std::span<Jacobian2> jac) const {
  if (jac.empty()) {
    std::copy(params.begin(), params.end(), x.begin());
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, params.size(), kPointBlock),
                    [&](const auto &r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        const Inversion inv = target_.invert(params[i]);
                        x[i] = inv.x;
                        jac[i] = inv.jacobian;
                      }
                    });
}

double DirectOptimizer::instanceLoss(std::size_t k, int epoch, std::span<const Point2> x,
                                     std::span<Point2> grad) const {
  const OptimizerSettings &s = settings_;
  double loss = setLoss(k, epoch, x, grad);
  if (s.nestedSizes.empty()) return loss;
  // Each prefix as a set of its own, weighted (m / n)^power, in a fixed
  // order (resumes stay bit-identical).
  std::vector<Point2> g(s.n);
  for (const std::size_t m : s.prefixSizes()) {
    if (m == s.n) break;
    const double w = std::pow(double(m) / double(s.n), s.nestedPower);
    const auto gm = std::span(g).first(m);
    std::fill(gm.begin(), gm.end(), Point2{});
    loss += w * setLoss(k, epoch, x.first(m), gm);
    for (std::size_t i = 0; i < m; ++i) grad[i] = grad[i] + w * gm[i];
  }
  return loss;
}

double DirectOptimizer::setLoss(std::size_t k, int epoch, std::span<const Point2> x,
                                std::span<Point2> grad) const {
  const OptimizerSettings &s = settings_;
  if (s.objective == Objective::ExactL2asd) return exactObjective_->squared(x, grad);
  if (s.objective == Objective::PeriodicL2) return periodicL2Squared(x, grad);
  Rng rng(hashCombine(s.seed, s.firstInstance + k), std::uint64_t(epoch));
  std::vector<Box2> boxes(s.boxes);
  std::vector<double> masses(s.boxes);
  sampleBoxes(s.boxKind, rng, boxes);
  if (s.mcSamples)
    MonteCarloBoxMass(target_, s.mcSamples).estimate(boxes, masses, rng);
  else
    exactBoxMasses(target_, boxes, masses);
  const double alpha = linearRamp(s.alphaStart, s.alphaEnd, s.rampFraction, epoch, s.epochs);
  return softBoxLoss(x, boxes, masses, {alpha, s.cutoff}, grad);
}

double DirectOptimizer::unionLoss(int epoch, std::span<const Point2> x,
                                  std::span<Point2> grad) const {
  const OptimizerSettings &s = settings_;
  const std::size_t n = s.n, K = s.instances, group = s.unionGroupSize();
  // A fresh partition every epoch (keyed by seed and epoch, so resumes stay
  // bit-identical): over the run every pair of instances meets.
  std::vector<std::size_t> order(K);
  for (std::size_t k = 0; k < K; ++k) order[k] = k;
  Rng rng(hashCombine(s.seed, 0x756e696f6eull), std::uint64_t(epoch));
  shuffle(std::span(order), rng);
  const std::size_t groups = (K + group - 1) / group;
  std::vector<double> losses(groups, 0.0);
  tbb::parallel_for(std::size_t(0), groups, [&](std::size_t g) {
    const std::size_t first = g * group, size = std::min(group, K - first);
    if (size < 2) return;  // a lone instance has no union to keep apart
    std::vector<Point2> u, gu(size * n);
    u.reserve(size * n);
    for (std::size_t j = 0; j < size; ++j) {
      const auto inst = x.subspan(order[first + j] * n, n);
      u.insert(u.end(), inst.begin(), inst.end());
    }
    const double w = s.unionWeight * double(size);
    losses[g] = w * exactObjective_->squared(u, gu);
    // Each group owns its instances' gradients: no two groups write one.
    for (std::size_t j = 0; j < size; ++j)
      for (std::size_t i = 0; i < n; ++i) {
        Point2 &out = grad[order[first + j] * n + i];
        out.x += w * gu[j * n + i].x;
        out.y += w * gu[j * n + i].y;
      }
  });
  double total = 0;
  for (double l : losses) total += l;
  return total / double(K);
}

void DirectOptimizer::constrain(std::span<Point2> params) const {
  // Mapped points are u, clamped to the unit square (the inverse CDF is not
  // periodic in u); unmapped ones go through the poles on the sphere and are
  // clamped, or wrapped when toroidal, on the square.
  const Domain domain = settings_.mapping == Mapping::Mapped ? Domain::Square : target_.domain();
  const bool toroidal = domain == Domain::Square && settings_.mapping == Mapping::Toroidal;
  for (Point2 &p : params) {
    if (!isFinite(p)) throw std::runtime_error("optimizer: a point became non-finite");
    p = toroidal ? Point2{wrapUnit(p.x), wrapUnit(p.y)} : wrapToDomain(p, domain);
  }
}

PointSet DirectOptimizer::points(const OptimizerState &state) const {
  PointSet set;
  set.n = settings_.n;
  set.points = state.params;
  if (settings_.mapping == Mapping::Mapped && !target_.isUniform())
    for (Point2 &p : set.points) p = target_.invert(p).x;
  recordTarget(set, target_);
  setMeta(set, meta::kGenerator, "optimized");
  setMeta(set, meta::kSettings, settings_.describe());
  setMeta(set, meta::kEpochsDone, std::to_string(state.epoch));
  if (!settings_.nestedSizes.empty()) {
    std::string sizes;
    for (const std::size_t m : settings_.prefixSizes())
      sizes += (sizes.empty() ? "" : ",") + std::to_string(m);
    setMeta(set, meta::kPrefixes, sizes);
  }
  return set;
}

namespace {
constexpr char kCheckpointMagic[8] = {'N', 'U', 'L', 'D', 'C', 'K', 'P', '1'};

void writeBlock(std::ostream &out, const void *data, std::size_t bytes) {
  out.write(static_cast<const char *>(data), std::streamsize(bytes));
}
void readBlock(std::istream &in, void *data, std::size_t bytes, const std::string &path) {
  in.read(static_cast<char *>(data), std::streamsize(bytes));
  if (!in) throw std::runtime_error(path + ": truncated checkpoint");
}
std::string fingerprint(const DirectOptimizer &opt, const std::string &targetSpec) {
  return opt.settings().describe() + " target=" + targetSpec;
}
}  // namespace

void saveCheckpoint(const std::string &path, const DirectOptimizer &opt,
                    const std::string &targetSpec, const OptimizerState &state) {
  std::ostringstream out;
  const std::string fp = fingerprint(opt, targetSpec);
  const std::uint64_t fpBytes = fp.size(), count = state.params.size(), K = state.lastLoss.size();
  const std::int64_t epoch = state.epoch;
  writeBlock(out, kCheckpointMagic, sizeof(kCheckpointMagic));
  writeBlock(out, &fpBytes, 8);
  writeBlock(out, fp.data(), fp.size());
  writeBlock(out, &epoch, 8);
  writeBlock(out, &count, 8);
  writeBlock(out, &K, 8);
  for (const auto *v : {&state.params, &state.m, &state.v})
    writeBlock(out, v->data(), count * sizeof(Point2));
  writeBlock(out, state.lastLoss.data(), K * sizeof(double));
  writeFileAtomically(path, out.str());
}

OptimizerState loadCheckpoint(const std::string &path, const DirectOptimizer &opt,
                              const std::string &targetSpec) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open checkpoint");
  char magic[8];
  readBlock(in, magic, 8, path);
  if (std::memcmp(magic, kCheckpointMagic, 8) != 0)
    throw std::runtime_error(path + ": not a nuld optimizer checkpoint");
  std::uint64_t fpBytes = 0, count = 0, K = 0;
  std::int64_t epoch = 0;
  readBlock(in, &fpBytes, 8, path);
  if (fpBytes > (1u << 20)) throw std::runtime_error(path + ": corrupt checkpoint header");
  std::string fp(fpBytes, '\0');
  readBlock(in, fp.data(), fpBytes, path);
  const std::string expected = fingerprint(opt, targetSpec);
  if (fp != expected)
    throw std::runtime_error(path + ": checkpoint was made with other settings:\n  checkpoint: " +
                             fp + "\n  requested:  " + expected);
  readBlock(in, &epoch, 8, path);
  readBlock(in, &count, 8, path);
  readBlock(in, &K, 8, path);
  const OptimizerSettings &s = opt.settings();
  if (count != s.n * s.instances || K != s.instances || epoch < 0 || epoch > s.epochs)
    throw std::runtime_error(path + ": checkpoint sizes do not match its settings");
  OptimizerState state;
  state.epoch = int(epoch);
  for (auto *v : {&state.params, &state.m, &state.v}) {
    v->resize(count);
    readBlock(in, v->data(), count * sizeof(Point2), path);
  }
  state.lastLoss.resize(K);
  readBlock(in, state.lastLoss.data(), K * sizeof(double), path);
  return state;
}

ResumableRun resumableRun(const DirectOptimizer &opt, const std::string &targetSpec,
                          OptimizerState &state,
                          std::function<void(const EpochReport &)> progress) {
  ResumableRun run;
  run.unit = "epoch";
  run.total = opt.settings().epochs;
  run.position = [&state] { return state.epoch; };
  run.advance = [&opt, &state, progress = std::move(progress)](int until) {
    opt.run(state, until, progress);
  };
  run.save = [&opt, &state, targetSpec](const std::string &path) {
    saveCheckpoint(path, opt, targetSpec, state);
  };
  run.load = [&opt, &state, targetSpec](const std::string &path) {
    state = loadCheckpoint(path, opt, targetSpec);
  };
  return run;
}

}  // namespace nuld
