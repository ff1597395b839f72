#include "sampler/targets/target_family.h"

#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>

#include "sampler/io/round_trip.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/target_spec.h"

namespace nuld {
namespace {

std::map<std::string, TargetFamilyFactory> &registry() {
  static std::map<std::string, TargetFamilyFactory> r;
  return r;
}
std::map<std::string, TargetDescription> &descriptions() {
  static std::map<std::string, TargetDescription> d;
  return d;
}
std::mutex &registryMutex() {
  static std::mutex m;
  return m;
}

// One target; gamma is empty.
class FixedFamily final : public TargetFamily {
 public:
  explicit FixedFamily(const std::string &spec) : target_(makeTarget(spec)) {}
  std::string spec() const override { return target_->spec(); }
  std::size_t gammaDimension() const override { return 0; }
  Domain domain() const override { return target_->domain(); }
  std::shared_ptr<const Target> target(std::span<const double> gamma) const override {
    checkGamma(*this, gamma);
    return target_;
  }

 private:
  std::shared_ptr<const Target> target_;
};

class GaussianFamily final : public TargetFamily {
 public:
  GaussianFamily(double sigmaMin, double sigmaMax) : min_(sigmaMin), max_(sigmaMax) {}
  std::string spec() const override {
    return "family:gaussian:" + formatRoundTrip(min_) + "," + formatRoundTrip(max_);
  }
  std::size_t gammaDimension() const override { return 3; }
  Domain domain() const override { return Domain::Square; }
  std::shared_ptr<const Target> target(std::span<const double> g) const override {
    checkGamma(*this, g);
    return std::make_shared<GaussianTarget>(g[0], g[1], min_ * std::pow(max_ / min_, g[2]));
  }

 private:
  double min_, max_;
};

class BilinearFamily final : public TargetFamily {
 public:
  std::string spec() const override { return "family:bilinear"; }
  std::size_t gammaDimension() const override { return 4; }
  Domain domain() const override { return Domain::Square; }
  std::shared_ptr<const Target> target(std::span<const double> g) const override {
    checkGamma(*this, g);
    // The floor keeps every member a proper density (weights not all zero).
    constexpr double kFloor = 0.05;
    return std::make_shared<BilinearTarget>(kFloor + g[0], kFloor + g[1], kFloor + g[2],
                                            kFloor + g[3]);
  }
};

}  // namespace

void registerTargetFamily(const std::string &name, TargetFamilyFactory factory,
                          const std::string &grammar, const std::string &description) {
  std::lock_guard lock(registryMutex());
  registry()[name] = std::move(factory);
  descriptions()[name] = {grammar.empty() ? "family:" + name + "[:ARGS]" : grammar, description};
}

std::vector<TargetDescription> targetFamilyDescriptions() {
  std::vector<TargetDescription> out{
      {"family:gaussian[:SMIN,SMAX]",
       "gamma = (mx, my, s): a Gaussian at (mx, my) with sigma = SMIN (SMAX/SMIN)^s "
       "(default 0.05, 0.3)"},
      {"family:bilinear", "gamma = the four corner weights (plus 0.05)"},
  };
  std::lock_guard lock(registryMutex());
  for (const auto &[name, d] : descriptions()) out.push_back(d);
  return out;
}

void checkGamma(const TargetFamily &family, std::span<const double> gamma) {
  if (gamma.size() != family.gammaDimension())
    throw std::invalid_argument("target family '" + family.spec() + "': gamma has " +
                                std::to_string(gamma.size()) + " entries, expected " +
                                std::to_string(family.gammaDimension()));
  for (double g : gamma)
    if (!(g >= 0 && g <= 1))
      throw std::invalid_argument("target family '" + family.spec() +
                                  "': gamma entries must lie in [0, 1], got " + std::to_string(g));
}

std::unique_ptr<TargetFamily> makeTargetFamily(const std::string &spec) {
  constexpr std::string_view kPrefix = "family:";
  if (spec.rfind(kPrefix, 0) != 0) return std::make_unique<FixedFamily>(spec);
  const std::string rest = spec.substr(kPrefix.size());
  const std::size_t colon = rest.find(':');
  const std::string name = rest.substr(0, colon);
  const std::string args = colon == std::string::npos ? "" : rest.substr(colon + 1);
  if (name == "gaussian") {
    double lo = 0.05, hi = 0.3;
    if (!args.empty()) {
      const auto v = parseNumberList(spec, args, 2, 2, "SIGMA_MIN,SIGMA_MAX");
      lo = v[0];
      hi = v[1];
    }
    if (!(lo > 0 && hi >= lo))
      throw std::invalid_argument("target family '" + spec +
                                  "': expected 0 < SIGMA_MIN <= SIGMA_MAX");
    return std::make_unique<GaussianFamily>(lo, hi);
  }
  if (name == "bilinear") {
    if (!args.empty())
      throw std::invalid_argument("target family '" + spec + "': bilinear takes no parameters");
    return std::make_unique<BilinearFamily>();
  }
  TargetFamilyFactory factory;
  {
    std::lock_guard lock(registryMutex());
    const auto it = registry().find(name);
    if (it != registry().end()) factory = it->second;
  }
  if (!factory) {
    std::string known = "gaussian, bilinear";
    for (const auto &[k, _] : registry()) known += ", " + k;
    throw std::invalid_argument("target family '" + spec + "': unknown family '" + name +
                                "' (known: " + known + ")");
  }
  return factory(args);
}

}  // namespace nuld
