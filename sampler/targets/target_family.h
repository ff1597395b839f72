#pragma once
// A family of targets indexed by a distribution parameter gamma (the neural
// generator's second input; docs/architecture.md, "Targets and
// families"). Gamma always lives in the unit cube
// [0,1]^k, so the Fourier encoding sees inputs of comparable scale; each family
// maps it to its natural parameters.
//
// Family SPECs:
//   family:gaussian[:SMIN,SMAX]  gamma = (mx, my, s), sigma = SMIN (SMAX/SMIN)^s
//                                (default 0.05 .. 0.3)
//   family:bilinear              gamma = corner weights, w = 0.05 + gamma
//   family:disney[:ARGS]         gamma = omega_o (added by the materials module)
//   any target SPEC              a fixed target, k = 0 (z is the only input)

#include <functional>
#include <memory>
#include <span>
#include <string>

#include "sampler/targets/target.h"
#include "sampler/targets/target_spec.h"

namespace nuld {

class TargetFamily {
 public:
  virtual ~TargetFamily() = default;
  virtual std::string spec() const = 0;
  virtual std::size_t gammaDimension() const = 0;
  virtual Domain domain() const = 0;
  // Throws std::invalid_argument unless gamma has gammaDimension() entries in [0, 1].
  // Shared: a fixed family hands out the one target it holds.
  virtual std::shared_ptr<const Target> target(std::span<const double> gamma) const = 0;
};

using TargetFamilyFactory = std::function<std::unique_ptr<TargetFamily>(const std::string &args)>;

// Adds `family:NAME[:ARGS]` (the materials module adds `disney`), with its
// line in targetFamilyDescriptions.
void registerTargetFamily(const std::string &name, TargetFamilyFactory factory,
                          const std::string &grammar = "", const std::string &description = "");

// Every family makeTargetFamily knows, built in and registered, as
// (grammar, description) pairs (`nuld help targets`).
std::vector<TargetDescription> targetFamilyDescriptions();

// Throws std::invalid_argument naming the spec and what was expected.
std::unique_ptr<TargetFamily> makeTargetFamily(const std::string &spec);

// Checks a gamma vector against a family; throws naming the family.
void checkGamma(const TargetFamily &family, std::span<const double> gamma);

}  // namespace nuld
