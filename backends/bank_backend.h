#pragma once
// Banks of point sets and the one backend that deals them out: the
// `optimized:PATHS` backend (point-set files written by `nuld optimize` or
// the studies) and, filled by a generator, `neural:MODEL`.
//
// A bank is K instances of N = spp points that follow one target (metadata
// `target`). At prepare() every bank is matched to the scene's sampling
// contexts (renderer/sampler_backend.h) by its target spec:
//  - a bank for the scene's environment map serves the first bounce's light
//    pair, a bank for a tabulated lobe (renderer/lobe_tables.h) the first
//    bounce's BSDF domain of the shading points that sample that table; one
//    instance is picked per (pixel, domain), as the paper does with its bank of
//    optimized sets, and dealt out in a random order;
//  - a bank for the uniform target serves the first bounce's 2D domains as
//    primary-sample-space points, one instance per (pixel, domain) under its
//    own Cranley-Patterson shift, which keeps the estimator unbiased.
// Every other domain and context (deeper bounces, other materials) falls back
// to Owen-scrambled Sobol with the same seed, bit for bit what `sobol` gives,
// except the first bounce's BSDF domains: unless a uniform bank serves them,
// they take the classic lobe routes with those points, as `sobol-tabulated`
// does (its tables built even where no bank is for a lobe), so that a bank's
// row measures what its sets add to the best classic mapping.
//
// Optimized instances of a non-uniform target are not randomized: the
// estimator's expectation is the average over the bank's points, which
// misses the target where the instances converge to nearly one set (glossy
// lobes do). `shifted:PATHS` randomizes them instead: each point is pulled
// back to primary space through the target's CDF map (GridTarget::primaryOf),
// the set is Cranley-Patterson shifted there per (pixel, domain), and mapped
// back through the inverse CDF, so every point follows the target exactly
// and the estimator is unbiased, at the price of the structure the shift
// cuts across the torus seams.

#include <array>
#include <atomic>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "renderer/sampler_backend.h"
#include "sampler/point.h"

namespace nuld {

struct SetBank {
  PointSet sets;       // K instances of N points
  std::string source;  // where they came from, for messages

  // The metadata's `target`, or "uniform" without one.
  std::string targetSpec() const;
  // Optimized as nested sets (metadata `prefixes`): its instances' first m
  // points serve a render of m spp, for any m up to N.
  bool nested() const;
};

// The banks of PATHS: point-set files or directories of them (every point-set
// file under a directory, its subdirectories included, in path order; not
// checkpoints nor hidden temporaries), separated by commas. Throws naming the
// path when one cannot be read, or holds no points.
std::vector<SetBank> loadSetBanks(const std::string &paths);

// How a bank's instance becomes the points of one estimate.
enum class Dealing {
  AsOptimized,  // its points (a nested bank's prefix), not randomized
  Shifted,      // pulled back through the target's CDF map, shifted there, mapped back
  Primary,      // primary points (a uniform bank): shifted, then mapped by the target if any
};
// A bank's dealing: Primary for a uniform bank, else Shifted or AsOptimized.
Dealing dealingOf(const SetBank &bank, bool shifted);

// The one way a bank's sets become the points of one estimate, in renders
// (BankBackend, an instance per pixel and domain) and in the integration
// study (one estimate per instance). A shift is a Cranley-Patterson
// rotation in primary space; mapped through the target's inverse CDF, it
// makes every point follow the target exactly and the estimate unbiased. A
// Shifted bank's points are pulled back through the target's CDF map
// (GridTarget::primaryOf) once, when the dealer is made.
class SetDealer {
 public:
  // `target`: what the dealt points follow (nullptr with Primary: primary
  // points, as the renderer's primary domains take them). Throws
  // std::invalid_argument naming the target when Shifted needs a CDF map
  // it does not have.
  SetDealer(const SetBank &bank, const Target *target, Dealing dealing);

  std::size_t instances() const { return bank_->sets.instances(); }
  bool shifts() const { return dealing_ != Dealing::AsOptimized; }
  // Instance k's first out.size() points, shifted by `shift` when the
  // dealer shifts (ignored otherwise); in the set's order.
  void deal(std::size_t k, std::uint64_t shift, std::span<Point2> out) const;

 private:
  const SetBank *bank_;
  const Target *target_;
  Dealing dealing_;
  std::vector<Point2> pulledBack_;  // Shifted: the bank's points in primary space
};

class BankBackend : public SamplerBackend {
 public:
  // `salt` keeps the instance choice of different kinds of bank independent.
  BankBackend(std::string name, std::vector<SetBank> banks, std::uint64_t seed,
              std::uint64_t salt = 0x6f7074696d697a65ull, bool shifted = false);

  std::string name() const override { return name_; }
  bool samplesLobes() const override;
  void prepare(std::size_t spp, const SamplingTargets &targets) override;
  void primary(std::uint64_t pixel, std::uint32_t domain, std::span<Point2> out) const override;
  // The fallback's: banks are 2D sets.
  void primary1D(std::uint64_t pixel, std::uint32_t domain, std::span<double> out) const override;
  bool distributed(const Target &target, std::uint64_t pixel, std::uint32_t domain,
                   std::span<Point2> out) const override;
  bool mapsPrimaryThrough(const Target &target) const override;
  Report report() const override;
  // Says when a bank without a `target` serves as uniform primary samples.

  const std::vector<SetBank> &banks() const { return banks_; }
  // How many of the scene's targets the last prepare() matched to a bank.
  std::size_t servedTargets() const { return served_.size(); }

 protected:
  // For a backend that makes its banks in prepare() (NeuralBackend).
  void setBanks(std::vector<SetBank> banks);
  // Whether every set is Cranley-Patterson shifted in primary space (as
  // `shifted:PATHS`); takes effect at the next prepare().
  void setShifted(bool shifted) { shifted_ = shifted; }
  // Whether prepare() accepts no banks at all, every pair then taking the
  // fallback (a generator whose every bank failed its serving test).
  void allowNoBanks(bool allow) { allowNoBanks_ = allow; }
  std::uint64_t seed() const { return seed_; }

 private:
  // The instance a pixel's domain takes of a bank of `instances`.
  std::size_t pick(std::size_t instances, std::uint64_t pixel, std::uint32_t domain) const;

  std::string name_;
  std::vector<SetBank> banks_;
  std::uint64_t seed_, salt_;
  std::unique_ptr<SamplerBackend> fallback_;
  bool shifted_;
  bool allowNoBanks_ = false;
  // The bounces, from the first, its sets serve: the registry's declaration
  // for banks (backends/backend_registry.h).
  int setBounces_;  // BackendEntry::setBounces
  // Set by prepare(): the served targets (by address) and their banks'
  // dealers; a uniform bank's, for the primary domains.
  struct Served {
    const Target *target;
    SetDealer dealer;
  };
  std::vector<Served> served_;
  std::optional<SetDealer> uniform_;
  std::string note_;  // note(), set by prepare()
  const Target *light_ = nullptr;
  std::vector<const Target *> lobes_;  // the scene's lobe tables (prepare())
  std::size_t n_ = 0;
  // pairUse()'s counts: light, bsdf, primary; relaxed atomics (a context is
  // asked once per pixel and domain, not per sample).
  struct Use {
    std::atomic<std::uint64_t> served{0}, fellBack{0};
  };
  mutable std::array<Use, 3> use_;
};

}  // namespace nuld
