#pragma once
// Sliced optimal transport sampling (Paulin et al. 2020; non-uniform as in
// Salaun et al. 2022), one of the seed's baselines: points move toward the
// target by matching their 1D projections to the target's along random
// directions.
//
// Each iteration draws `slices` directions theta on the unit circle. Along
// each, the N projections p_i . theta are sorted and the point of rank k is
// sent to the mean of the target's k-th slab of mass 1/N along theta (the
// 1D optimal transport of N equal masses): in closed form for the uniform
// square, whose projection has a trapezoid density, and for any other
// target the mean of the k-th block of a fixed stratified sample of it
// (Owen-scrambled Sobol through its inverse CDF), projected and sorted.
// The slab's mean, not its (k + 1/2)/N quantile, is where the 1D optimal
// transport of an equal mass 1/N ends, and it keeps the set's mean
// projection equal to the target's along every direction. Sorting that sample for every slice
// would dominate the run, so its block means are tabulated once per target
// and N at kSliceTableDirections directions over a half-turn and
// interpolated linearly in angle between them. A point moves by `step`
// times its displacement averaged over the slices, then is clamped into
// [0, 1)^2.
//
// On the sphere (a target whose domain is the sphere or hemisphere) the
// points live in the equal-area parameterization and transport against the
// target mapped there, the approximation the supplement used; longitude is
// not treated as periodic.

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

struct SlicedOtSettings {
  int iterations = 1024;
  int slices = 64;  // directions per iteration
  double step = 1;  // fraction of the averaged displacement applied
  // Size of the target's stratified sample (0: max(64 N, 16384)); unused for
  // the uniform target, whose projections are exact.
  std::size_t targetSamples = 0;
  std::uint64_t seed = 0;

  std::size_t samplesFor(std::size_t n) const;
  std::string describe() const;  // "iterations=... slices=..." for metadata
  void validate() const;         // throws std::invalid_argument naming the setting
};

// The means of the N slabs of mass 1/N, ascending, of theta . X for X
// uniform on the unit square (theta a unit vector).
void uniformProjectionSlabMeans(Point2 theta, std::span<double> out);

// Where the point of each rank goes along a direction, for one target and
// N: built once, shared by every instance (and thread).
class SliceDestinations {
 public:
  static constexpr int kSliceTableDirections = 1024;
  SliceDestinations(const Target &target, const SlicedOtSettings &settings, std::size_t n);
  std::size_t size() const { return n_; }
  // The N destinations along unit vector theta, ascending.
  void along(Point2 theta, std::span<double> out) const;

 private:
  bool uniform_;
  std::size_t n_;
  std::vector<double> table_;  // [direction][rank] block means, directions at pi d / D
};

// Moves `points` (initial positions; N = destinations.size() >= 1) toward
// the target. Instance `instance` draws its own directions from
// (settings.seed, instance). `progress(iteration)` is called every
// iteration when given.
void slicedOtTransport(const SliceDestinations &destinations, const SlicedOtSettings &settings,
                       std::uint32_t instance, std::span<Point2> points,
                       const std::function<void(int)> &progress = {});

}  // namespace nuld
