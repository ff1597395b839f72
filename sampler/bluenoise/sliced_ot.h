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
// projection equal to the target's along every direction.
//
// Uniform sets are transported, by default, in the disc inscribed in the
// square and carried to the square by an area-preserving map, as the
// authors' code does (it optimizes in the ball, then maps to the cube): the
// disc's projections are the same along every direction and it has no
// corners, and sets transported there match the authors' program where
// sets transported in the square do not (tools/experiments/blue_noise.md).
// Sorting that sample for every slice would dominate the run, so its block
// means are tabulated once per target and N at kSliceTableDirections directions
// over a half-turn and interpolated linearly in angle between them. A point
// moves by `step` times its displacement averaged over the slices, then is
// clamped into [0, 1)^2.
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

// Where uniform sets are transported (UniformSotDomain::Disc: see above).
enum class UniformSotDomain { Disc, Square };
inline constexpr auto kUniformSotDomainNames = enumTable<UniformSotDomain>(
    "uniform domain", {{"disc", UniformSotDomain::Disc}, {"square", UniformSotDomain::Square}});
constexpr const auto &enumNames(UniformSotDomain) { return kUniformSotDomainNames; }
inline UniformSotDomain parseUniformSotDomain(const std::string &name) {
  return kUniformSotDomainNames.parse(name);
}

struct SlicedOtSettings {
  int iterations = 1024;
  int slices = 64;  // directions per iteration
  double step = 1;  // fraction of the averaged displacement applied
  // Size of the target's stratified sample (0: max(64 N, 16384)); unused for
  // the uniform target, whose projections are exact.
  std::size_t targetSamples = 0;
  std::uint64_t seed = 0;
  UniformSotDomain uniformDomain = UniformSotDomain::Disc;  // uniform targets only

  std::size_t samplesFor(std::size_t n) const;
  std::string describe() const;  // "iterations=... slices=..." for metadata
  void validate() const;         // throws std::invalid_argument naming the setting
};

// The means of the N slabs of mass 1/N, ascending, of theta . X for X
// uniform on the unit square (theta a unit vector).
void uniformProjectionSlabMeans(Point2 theta, std::span<double> out);

// The same for the uniform disc of radius 1/2 centred at the origin, the
// same along every direction.
void uniformDiscSlabMeans(std::span<double> out);

// Shirley and Chiu's concentric map from the unit square onto the disc of
// radius 1/2 centred at (1/2, 1/2), area-preserving and continuous, and its
// inverse (which lands in [0, 1)^2).
Point2 squareToDisc(Point2 u);
Point2 discToSquare(Point2 p);

// Where the point of each rank goes along a direction, for one target and
// N: built once, shared by every instance (and thread).
class SliceDestinations {
 public:
  static constexpr int kSliceTableDirections = 1024;
  SliceDestinations(const Target &target, const SlicedOtSettings &settings, std::size_t n);
  std::size_t size() const { return n_; }
  // The N destinations along unit vector theta, ascending.
  void along(Point2 theta, std::span<double> out) const;
  // Whether the points travel in the inscribed disc (a uniform target with
  // UniformSotDomain::Disc) rather than the square.
  bool inDisc() const { return disc_; }

 private:
  bool uniform_, disc_;
  std::size_t n_;
  // [direction][rank] block means, directions at pi d / D; for the disc one
  // row, centred at 0.
  std::vector<double> table_;
};

// Moves `points` (initial positions in the square; N = destinations.size()
// >= 1) toward the target; in the disc, they are carried there by
// squareToDisc first and back by discToSquare at the end. Instance `instance` draws its own
// directions from (settings.seed, instance). `progress(iteration)` is called every iteration when
// given.
void slicedOtTransport(const SliceDestinations &destinations, const SlicedOtSettings &settings,
                       std::uint32_t instance, std::span<Point2> points,
                       const std::function<void(int)> &progress = {});

}  // namespace nuld
