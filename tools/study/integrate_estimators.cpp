// The estimators of the integration study (integrate_estimators.h): one
// importance-sampling estimate per point set, one estimator per sampler
// kind, and the statistics over a sampler's instances.
#include "tools/study/integrate_estimators.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "backends/stopwatch.h"
#include "sampler/bluenoise/blue_noise_sets.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"
#include "tools/study/statistics.h"

namespace nuld::study {

double importanceEstimate(const Integrand &in, std::span<const Point2> points,
                          std::size_t &zeroPdf) {
  double sum = 0;
  for (const Point2 &x : points) {
    const double p = isFinite(x) ? in.target->pdf(x) : 0.0;
    const double v = p > 0 ? in.f(x) / p : 0.0;
    if (!(p > 0) || !std::isfinite(v)) {
      ++zeroPdf;
      continue;
    }
    sum += v;
  }
  return points.empty() ? 0.0 : sum / double(points.size());
}

EstimateStats summarize(std::span<const double> e, double reference) {
  if (e.size() < 2) throw std::invalid_argument("summarize: need at least 2 estimates");
  const MeanAndError estimates = meanAndError(e);
  // The MSE is itself a mean over the instances: its standard error decides
  // whether two samplers' MSEs differ (heavy-tailed on HDR integrands).
  std::vector<double> squaredErrors;
  for (double v : e) squaredErrors.push_back((v - reference) * (v - reference));
  const MeanAndError mse = meanAndError(squaredErrors);
  EstimateStats s;
  s.mean = estimates.mean;
  s.std = estimates.std;
  s.bias = s.mean - reference;
  s.biasStderr = estimates.stderr_;
  s.rmse = std::sqrt(mse.mean);
  s.mseStderr = mse.stderr_;
  s.relRmse = reference != 0 ? s.rmse / std::abs(reference) : NAN;
  return s;
}

namespace {

// A row's seed, keyed by the estimator's name as it was before the classic
// words changed meaning (then `sobol` was a lobe integrand's table and
// `sobol-lobes` its BRDF sample()), so every row keeps the numbers it had.
std::uint64_t rowSeed(const IntegrateOptions &o, const Integrand &in, const SamplerChoice &s,
                      std::size_t n) {
  std::string key = s.name;
  const bool classic = s.kind == SamplerChoice::Kind::Classic;
  if (classic && s.tabulated) key.resize(key.size() - std::string_view("-tabulated").size());
  if (classic && !s.tabulated && in.lobeContribution) key += "-lobes";
  return hash3(o.seed, hashString(in.name + "|" + key), n);
}

// A classic sampler's sets (in its randomization), through the BRDF's own
// sample() on a lobe integrand (unless tabulated), else the target's inverse
// CDF.
class ClassicEstimator final : public Estimator {
 public:
  ClassicEstimator(const IntegrateOptions &o, const SamplerChoice &s) : o_(o), s_(s) {}
  Measurement measure(const Integrand &in, std::size_t n) const override {
    const SequenceOptions so{s_.sequence, s_.scramble, rowSeed(o_, in, s_, n)};
    Measurement m;
    std::vector<Point2> u(n), x(n);
    for (std::size_t k = 0; k < o_.instances; ++k) {
      const auto start = Clock::now();
      generateSet(so, std::uint32_t(k), u);
      if (!s_.tabulated && in.lobeContribution) {
        // sample() makes the direction, f and the pdf in one call, so the
        // time of such a set covers its whole evaluation.
        double sum = 0;
        for (const Point2 &ui : u) {
          const double v = in.lobeContribution(ui);
          if (std::isfinite(v))
            sum += v;
          else
            ++m.zeroPdf;
        }
        m.genSeconds += secondsSince(start);
        m.estimates.push_back(sum / double(n));
        continue;
      }
      for (std::size_t i = 0; i < n; ++i) x[i] = in.target->invert(u[i]).x;
      m.genSeconds += secondsSince(start);
      m.estimates.push_back(importanceEstimate(in, x, m.zeroPdf));
    }
    m.genSeconds /= double(o_.instances);
    return m;
  }

 private:
  const IntegrateOptions &o_;
  const SamplerChoice &s_;
};

// The runner's optimized sets for the integrand's own target, one estimate
// per set.
class OptimizedEstimator final : public Estimator {
 public:
  OptimizedEstimator(const IntegrateOptions &o, OptimizedBank bank)
      : o_(o), bank_(std::move(bank)) {}
  Measurement measure(const Integrand &in, std::size_t n) const override {
    double setupPerSet = 0;
    const PointSet bank = bank_(*in.target, n, setupPerSet);
    Measurement m;
    m.setupSeconds = setupPerSet;
    std::vector<Point2> x(n);
    for (std::size_t k = 0; k < o_.optimizedInstances; ++k) {
      const auto start = Clock::now();
      const auto set = bank.instance(k);
      std::copy(set.begin(), set.end(), x.begin());
      m.genSeconds += secondsSince(start);
      m.estimates.push_back(importanceEstimate(in, x, m.zeroPdf));
    }
    m.genSeconds /= double(o_.optimizedInstances);
    return m;
  }

 private:
  const IntegrateOptions &o_;
  OptimizedBank bank_;
};

// The blue-noise baselines (sampler/bluenoise/blue_noise_sets.h), K sets
// from independent starts, each method at its own defaults.
class BlueNoiseEstimator final : public Estimator {
 public:
  BlueNoiseEstimator(const IntegrateOptions &o, const SamplerChoice &s) : o_(o), s_(s) {}
  Measurement measure(const Integrand &in, std::size_t n) const override {
    const std::size_t K = o_.optimizedInstances;
    BlueNoiseRequest request = parseBlueNoiseName(s_.name);
    request.seed = rowSeed(o_, in, s_, n);
    const auto start = Clock::now();
    const PointSet sets = blueNoiseSets(request, *in.target, n, K);
    Measurement m;
    m.genSeconds = secondsSince(start) / double(K);
    for (std::size_t k = 0; k < K; ++k)
      m.estimates.push_back(importanceEstimate(in, sets.instance(k), m.zeroPdf));
    return m;
  }

 private:
  const IntegrateOptions &o_;
  const SamplerChoice &s_;
};

// The estimates of a bank's sets dealt as the renderer deals them
// (SetDealer): as optimized, one per instance, or shifted,
// `optimizedInstances` of them cycling through the instances, instance k
// under the shift hash3(row seed, k, 0).
Measurement dealtEstimates(const IntegrateOptions &o, const Integrand &in, const SamplerChoice &s,
                           const SetBank &bank, Dealing dealing, std::size_t n) {
  Measurement m;
  const auto start = Clock::now();
  const SetDealer dealer = [&] {
    try {
      return SetDealer(bank, in.target.get(), dealing);
    } catch (const std::invalid_argument &e) {
      throw std::runtime_error("--samplers '" + s.name + "': integrand '" + in.name +
                               "': " + e.what());
    }
  }();
  m.genSeconds = secondsSince(start);
  const std::size_t K = dealer.shifts() ? o.optimizedInstances : dealer.instances();
  std::vector<Point2> x(n);
  for (std::size_t k = 0; k < K; ++k) {
    const auto dealStart = Clock::now();
    dealer.deal(k % dealer.instances(), hash3(rowSeed(o, in, s, n), k, 0), x);
    m.genSeconds += secondsSince(dealStart);
    m.estimates.push_back(importanceEstimate(in, x, m.zeroPdf));
  }
  m.genSeconds /= double(K);
  return m;
}

// A bank word's sets from files (planTasks chose the bank per integrand and
// N): the integrand's own target's as optimized, or shifted; uniform sets
// shifted and mapped by the inverse CDF.
class BankEstimator final : public Estimator {
 public:
  BankEstimator(const IntegrateOptions &o, const SamplerChoice &s, const SetBank &bank)
      : o_(o), s_(s), bank_(bank) {}
  Measurement measure(const Integrand &in, std::size_t n) const override {
    return dealtEstimates(o_, in, s_, bank_, dealingOf(bank_, s_.shifted), n);
  }

 private:
  const IntegrateOptions &o_;
  const SamplerChoice &s_;
  const SetBank &bank_;
};

// A neural model's sets for the integrand's gamma, generated per row and
// dealt as the renderer deals them.
class NeuralEstimator final : public Estimator {
 public:
  NeuralEstimator(const IntegrateOptions &o, const SamplerChoice &s, const NeuralModel &model)
      : o_(o), s_(s), model_(model) {}
  Measurement measure(const Integrand &in, std::size_t n) const override {
    const std::size_t K = o_.optimizedInstances;
    const auto start = Clock::now();
    const SetBank bank{
        model_.generator->generateSets(K, rowSeed(o_, in, s_, n), model_.gammaFor.at(in.name), n),
        s_.name};
    const double seconds = secondsSince(start) / double(K);
    Measurement m =
        dealtEstimates(o_, in, s_, bank, s_.shifted ? Dealing::Shifted : Dealing::AsOptimized, n);
    m.genSeconds += seconds;
    return m;
  }

 private:
  const IntegrateOptions &o_;
  const SamplerChoice &s_;
  const NeuralModel &model_;
};

}  // namespace

std::unique_ptr<Estimator> makeEstimator(const IntegrateOptions &o, const SamplerChoice &s,
                                         const NeuralModel *model, const SetBank *bank,
                                         OptimizedBank optimizedBank) {
  using K = SamplerChoice::Kind;
  switch (s.kind) {
    case K::Optimized: return std::make_unique<OptimizedEstimator>(o, std::move(optimizedBank));
    case K::BlueNoise: return std::make_unique<BlueNoiseEstimator>(o, s);
    case K::Bank:
      if (!bank) throw std::logic_error("makeEstimator: a bank word's row without its bank");
      return std::make_unique<BankEstimator>(o, s, *bank);
    case K::Neural:
      if (!model) throw std::logic_error("makeEstimator: a neural row without its model");
      return std::make_unique<NeuralEstimator>(o, s, *model);
    case K::Classic: break;
  }
  return std::make_unique<ClassicEstimator>(o, s);
}

}  // namespace nuld::study
