#pragma once
// A fixed uniform target on the sphere, registered as `family:test-sphere`
// (the real sphere families need an environment map or the materials module).

#include "sampler/targets/basic_targets.h"
#include "sampler/targets/target_family.h"

namespace nuld::test {

class UniformSphereFamily final : public TargetFamily {
 public:
  std::string spec() const override { return "family:test-sphere"; }
  std::size_t gammaDimension() const override { return 0; }
  Domain domain() const override { return Domain::Sphere; }
  std::shared_ptr<const Target> target(std::span<const double>) const override {
    return std::make_shared<UniformTarget>(Domain::Sphere);
  }
};

inline void registerTestSphereFamily() {
  registerTargetFamily("test-sphere",
                       [](const std::string &) { return std::make_unique<UniformSphereFamily>(); });
}

}  // namespace nuld::test
