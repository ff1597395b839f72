#pragma once
// The integration study's estimators (integration_study.h): one per sampler
// kind, each turning an integrand and N into K importance-sampling
// estimates and the seconds one set took. The runner (integration_study.cpp)
// plans the rows, makes the optimized banks and writes the CSV; a row asks
// its estimator for the measurement and nothing else.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "backends/bank_backend.h"
#include "sampler/neural/neural_generator.h"
#include "tools/study/integration_study.h"

namespace nuld::study {

// A loaded neural model and the integrands it serves (with their gamma).
struct NeuralModel {
  std::string path, name;
  std::shared_ptr<const NeuralGenerator> generator;
  std::map<std::string, std::vector<double>> gammaFor;  // integrand name -> gamma
};

// One (integrand, sampler, N) measurement: K estimates and the time per set.
struct Measurement {
  std::vector<double> estimates;
  double genSeconds = 0, setupSeconds = 0;  // per set
  std::size_t zeroPdf = 0;                  // points that counted 0 (importanceEstimate)
};

class Estimator {
 public:
  virtual ~Estimator() = default;
  virtual Measurement measure(const Integrand &in, std::size_t n) const = 0;
};

// The optimized sampler's sets: K optimized sets of N points for a target
// (the runner's, from the set cache) and the optimization's seconds per set.
using OptimizedBank =
    std::function<PointSet(const Target &target, std::size_t n, double &secondsPerSet)>;

// The estimator of sampler `s`: classic samplers with `o.instances` Owen-
// scrambled sets (through the BRDF's sample() or the target's inverse CDF),
// `optimized` with the runner's bank, the blue-noise baselines, a bank
// word's `bank` and a neural `model`, each dealt as the renderer deals them
// (SetDealer); the last three with `o.optimizedInstances` sets.
std::unique_ptr<Estimator> makeEstimator(const IntegrateOptions &o, const SamplerChoice &s,
                                         const NeuralModel *model, const SetBank *bank,
                                         OptimizedBank optimizedBank);

}  // namespace nuld::study
