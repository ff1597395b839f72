#pragma once
// The direct optimizer (Algorithm 1; docs/architecture.md, "The direct
// optimizer"): the points of K instances
// are the parameters, moved by Adam on the soft box discrepancy against a
// target, with fresh boxes every epoch.
//
// Mappings: `mapped` optimizes u in the unit square and measures T(u), T the
// target's inverse CDF (gradients pulled back through its Jacobian), u
// clamped; `clamp` and `toroidal` optimize the points themselves, clamped to
// or wrapped around the square. On the sphere, unmapped points that leave
// through a pole come back on the other side: (u + 1/2, -v) or (u + 1/2, 2 - v),
// and u is periodic.
//
// Every random choice is keyed by (seed, instance, epoch), and all sums are
// in a fixed order, so a run resumed from a checkpoint ends bit-identical to
// an uninterrupted one.

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sampler/loss/boxes.h"
#include "sampler/metrics/nonuniform_l2.h"
#include "sampler/optimize/resumable_run.h"
#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

enum class Mapping { Mapped, Clamp, Toroidal };
// ExactL2asd: the closed-form expectation of the hard box loss, for uniform
// and piecewise-constant (grid) targets. PeriodicL2: the closed-form periodic
// L2 discrepancy (periodicL2Squared), uniform target and toroidal mapping
// only: a set whose quality any Cranley-Patterson shift keeps, to be shifted
// and then mapped to a target by its inverse CDF (`nuld map --shifts`).
enum class Objective { SoftBoxes, ExactL2asd, PeriodicL2 };

inline constexpr auto kMappingNames = enumTable<Mapping>(
    "mapping",
    {{"mapped", Mapping::Mapped}, {"clamp", Mapping::Clamp}, {"toroidal", Mapping::Toroidal}});
inline constexpr auto kObjectiveNames =
    enumTable<Objective>("objective", {{"soft", Objective::SoftBoxes},
                                       {"l2asd", Objective::ExactL2asd},
                                       {"l2per", Objective::PeriodicL2}});
constexpr const auto &enumNames(Mapping) { return kMappingNames; }
constexpr const auto &enumNames(Objective) { return kObjectiveNames; }
inline Mapping parseMapping(const std::string &s) { return kMappingNames.parse(s); }
inline Objective parseObjective(const std::string &s) { return kObjectiveNames.parse(s); }

struct OptimizerSettings {
  std::string preset = "custom";
  std::size_t n = 256;
  std::size_t instances = 1;
  int epochs = 2000;
  std::size_t boxes = 8192;
  BoxKind boxKind = BoxKind::MultipleCorner;
  std::size_t mcSamples = 0;  // 0: exact box mass; else Monte Carlo with this many space samples
  Mapping mapping = Mapping::Mapped;
  Objective objective = Objective::SoftBoxes;
  double lrStart = 1e-3, lrEnd = 1e-7;
  double alphaStart = 20, alphaEnd = 2000, rampFraction = 0.5;
  double cutoff = 36;
  std::uint64_t seed = 0;
  // The bank term (l2asd only): w * |G| * L2asd^2 of the union of each group
  // G of `unionGroup` instances, regrouped every epoch. A peaked target has
  // one best set, and instances optimized apart converge to it, so a bank
  // that draws one instance per pixel estimates against the average of its
  // sets, not the target (tools/experiments/lobe_banks_log.md §4). The term
  // keeps the instances complementary: their union must follow the target
  // too. 0 (the default) optimizes the instances independently. A group
  // costs O((|G| N)^2) per epoch, so by default (unionGroup 0) it holds
  // about 256 points: 16 instances at N = 16, 4 at N = 64, at least 2 and
  // at most all of them.
  double unionWeight = 0;
  std::size_t unionGroup = 0;
  // These are instances [firstInstance, firstInstance + instances) of a
  // larger run: instance k starts and draws its boxes as instance
  // firstInstance + k would, so a run split into parts (one per MPI rank)
  // makes the same sets as one run. Not with the bank term, which couples
  // the instances.
  std::size_t firstInstance = 0;
  // Nested sets: each instance's first m points are optimized as an m-point
  // set too, for every m in nestedSizes (ascending, each below n): the loss
  // is the full set's plus (m / n)^nestedPower times each prefix's, so one
  // bank serves every sample count up to n (a render at m spp takes the
  // first m points). The prefixes share the epoch's boxes. Empty (the
  // default): the full set only. nestedChain(4, 64) = 4, 8, 16, 32.
  std::vector<std::size_t> nestedSizes;
  double nestedPower = 1;
  // The prefix sizes the loss covers, ascending, n last ({n} when not nested).
  std::vector<std::size_t> prefixSizes() const;
  std::size_t unionGroupSize() const {
    if (unionGroup) return unionGroup;
    return std::min(instances, std::max<std::size_t>(2, 256 / std::max<std::size_t>(n, 1)));
  }

  // One line "key=value ..." naming every setting; checkpoints must match it.
  std::string describe() const;
  // Throws std::invalid_argument naming the bad setting.
  void validate() const;
};

// Powers of 2 times `from` below n: the prefixes of a fully nested set.
std::vector<std::size_t> nestedChain(std::size_t from, std::size_t n);

// The supplement's settings (§2, §3):
//   uniform      2000 epochs, lr 1e-3 -> 1e-7, alpha 20 -> 2000, 8K boxes
//                (N >= 2048: lr 1e-4, alpha -> 6000, 32K boxes)
//   nonuniform   1000 epochs, lr 1e-4 -> 1e-7, alpha 20 -> 2000, 8K boxes, exact mass
//                (N >= 2048: alpha -> 6000, 32K boxes)
//   nonuniform-mc  as nonuniform with MC mass, K = 2^17, 4K boxes (32K for N >= 2048)
//   sphere       5000 epochs, 16384 boxes (N <= 64: 2048), lr 1e-4 -> 1e-7,
//                alpha 20 -> 6000, exact mass
//   sphere-mc    as sphere with MC mass, K = 65536 (the paper's 460 s GPU setting)
//   sphere-exact (ours) the exact L2asd with the bank term (weight 3), 500 epochs,
//                lr 1e-2 -> 1e-5: the render study's environment-map sets
OptimizerSettings presetSettings(const std::string &name, std::size_t n);
// The preset matching a target: uniform, sphere or nonuniform.
std::string defaultPreset(const Target &target);

struct OptimizerState {
  int epoch = 0;                 // epochs completed
  std::vector<Point2> params;    // instances * n: u (mapped) or x
  std::vector<Point2> m, v;      // Adam moments
  std::vector<double> lastLoss;  // per instance, loss of the last epoch
};

struct EpochReport {
  int epoch = 0, epochs = 0;  // epoch just completed (1-based)
  double loss = 0;            // mean over instances
  double unionLoss = 0;       // the bank term per instance (0 when off)
  double alpha = 0, lr = 0;
};

class DirectOptimizer {
 public:
  DirectOptimizer(const Target &target, OptimizerSettings settings);

  const OptimizerSettings &settings() const { return settings_; }
  // Owen-scrambled Sobol (instance k scrambled with seed hash(seed, k)), as u
  // when mapped and as the points themselves when not.
  OptimizerState initialState() const;
  // Runs epochs [state.epoch, untilEpoch). `progress` is called after each
  // epoch.
  void run(OptimizerState &state, int untilEpoch,
           const std::function<void(const EpochReport &)> &progress = {}) const;
  // The points in the target's domain.
  PointSet points(const OptimizerState &state) const;

 private:
  // Each epoch maps the parameters to the target's domain once (x, and the
  // inverse CDF's Jacobians when mapped), adds the losses' gradients there,
  // and pulls their sum back once.
  void mapToTarget(std::span<const Point2> params, std::span<Point2> x,
                   std::span<Jacobian2> jac) const;
  // Instance k's own loss at its points x (with its prefixes' when nested);
  // writes its gradient in `grad`.
  double instanceLoss(std::size_t k, int epoch, std::span<const Point2> x,
                      std::span<Point2> grad) const;
  // The objective of one set of points (a whole instance or a prefix).
  double setLoss(std::size_t k, int epoch, std::span<const Point2> x, std::span<Point2> grad) const;
  // The bank term at all instances' points x; adds its gradient to `grad`
  // and returns its value per instance.
  double unionLoss(int epoch, std::span<const Point2> x, std::span<Point2> grad) const;
  void constrain(std::span<Point2> params) const;

  const Target &target_;
  OptimizerSettings settings_;
  std::shared_ptr<const NonuniformL2asd> exactObjective_;  // objective l2asd only
};

// Checkpoints: the settings description, the target spec and the state.
void saveCheckpoint(const std::string &path, const DirectOptimizer &opt,
                    const std::string &targetSpec, const OptimizerState &state);
// Throws naming the file when it is unreadable or made with other settings.
OptimizerState loadCheckpoint(const std::string &path, const DirectOptimizer &opt,
                              const std::string &targetSpec);

// `state`'s epochs as a run for driveRun, checkpointed by the functions above;
// `state` and `opt` must outlive the returned run.
ResumableRun resumableRun(const DirectOptimizer &opt, const std::string &targetSpec,
                          OptimizerState &state,
                          std::function<void(const EpochReport &)> progress = {});

}  // namespace nuld
