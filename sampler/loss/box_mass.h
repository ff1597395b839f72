#pragma once
// Target mass of sampled boxes: exact (the default; docs/architecture.md,
// "Targets and families") or the
// supplement's Monte Carlo estimate from K space samples per epoch.

#include <span>

#include "sampler/point.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/target.h"

namespace nuld {

void exactBoxMasses(const Target &target, std::span<const Box2> boxes, std::span<double> out);

// mu(A) ~= (1/K) sum_k 1_A(s_k) q(s_k) / p(s_k) with s_k uniform on the
// square (p = 1; uniform on the sphere too, the map being equal-area).
// Fresh space samples on every call, as in Algorithm 1.
class MonteCarloBoxMass {
 public:
  MonteCarloBoxMass(const Target &target, std::size_t samples) : target_(target), k_(samples) {}
  void estimate(std::span<const Box2> boxes, std::span<double> out, Rng &rng) const;
  std::size_t samples() const { return k_; }

 private:
  const Target &target_;
  std::size_t k_;
};

}  // namespace nuld
