#pragma once
// Gaussian blue noise (Ahmed, Ren and Wonka 2022), one of the seed's
// baselines: points descend an energy in which they repel each other through
// a Gaussian kernel and are attracted by the target's mass seen through the
// same kernel (a maximum mean discrepancy with a Gaussian kernel).
//
// With kernel k_s(d) = exp(-|d|^2 / (4 s^2)), s = sigma / sqrt(2 N) for the
// uniform target (sigma in units of the mean spacing 1/sqrt(N), the
// authors' "filtering" sigma; 1 by default), each iteration moves every point
// by `step` times
//   sum_j (p_i - p_j) k_s(p_i - p_j)  +  attraction_i,
// the energy's negative gradient scaled by s^2 (so the step is dimensionless,
// as the authors scale theirs):
//  - bounded (the square): attraction_i is the gradient of N int k_s(p_i -
//    x) dx over the square, in closed form with erf (it holds points off the
//    edges exactly as much as the missing neighbours beyond them would);
//  - toroidal: differences wrap, and the uniform attraction is constant;
//  - adaptive (any other target, in the square): point i's width follows
//    the target's density rho there, s_i = sigma / sqrt(2 N rho(p_i))
//    (bounded to [s / 8, 8 s] so that dim and 1e6-bright regions stay
//    finite; s itself off the support), a pair uses s_ij^2 = (s_i^2 +
//    s_j^2) / 2, and the
//    attraction is the kernel's pull toward a fixed stratified sample of the
//    target (Owen-scrambled Sobol through its inverse CDF, M points of mass
//    N / M each), the same sample-based target as sliced_ot.h.
// No point moves more than s_i / 2 per iteration (a trust region; without it
// the authors' step blew up sets on a peaked Gaussian target).
// Pairs farther apart than 8 s_ij (where the kernel is below 1.2e-7 of its
// peak) are skipped through a bucket grid; the forces then agree with the
// all-pairs sum to 1e-5 of their size (tested). A point's search radius is
// 8 sqrt((s_i^2 + S^2) / 2), S the largest width in the set, so no pair
// within its cutoff is missed; sets whose widths vary a lot pay for it.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

enum class BlueNoiseBoundary { Bounded, Toroidal };
inline constexpr auto kBlueNoiseBoundaryNames = enumTable<BlueNoiseBoundary>(
    "boundary",
    {{"bounded", BlueNoiseBoundary::Bounded}, {"toroidal", BlueNoiseBoundary::Toroidal}});
constexpr const auto &enumNames(BlueNoiseBoundary) { return kBlueNoiseBoundaryNames; }

struct GaussianBlueNoiseSettings {
  int iterations = 1000;
  double sigma = 1;    // kernel width in units of the mean spacing
  double step = 0.25;  // the authors' time step for sigma <= 1
  BlueNoiseBoundary boundary = BlueNoiseBoundary::Bounded;
  std::size_t targetSamples = 0;  // adaptive: 0 = max(4 N, 4096)
  std::uint64_t seed = 0;

  std::size_t samplesFor(std::size_t n) const;
  std::string describe() const;
  void validate() const;  // throws std::invalid_argument naming the setting
};

// The forces of one iteration (before `step`) on `points` for `target`:
// exposed for the tests, which compare them with finite differences of
// gaussianBlueNoiseEnergy and with the all-pairs sum.
class GaussianBlueNoise {
 public:
  GaussianBlueNoise(const Target &target, const GaussianBlueNoiseSettings &settings, std::size_t n);
  std::size_t size() const { return n_; }
  // Negative energy gradient times s^2; `allPairs` skips the cutoff grid.
  void forces(std::span<const Point2> points, std::span<Point2> out, bool allPairs = false) const;
  // The energy (uniform targets; scaled like forces()), for the tests.
  double energy(std::span<const Point2> points) const;
  // Moves `points` for settings.iterations iterations, keeping them in the
  // square; progress(iteration) after each when given.
  void optimize(std::span<Point2> points, const std::function<void(int)> &progress = {}) const;

 private:
  double widthAt(Point2 p) const;  // s_i
  // forces() with each point's width s_i given (optimize() reuses them).
  void forces(std::span<const Point2> points, std::span<const double> width, std::span<Point2> out,
              bool allPairs = false) const;

  const Target &target_;
  GaussianBlueNoiseSettings settings_;
  std::size_t n_;
  double s_;  // the uniform width sigma / sqrt(2 N)
  bool adaptive_;
  std::vector<Point2> sample_;  // adaptive: the target's stratified sample
  std::vector<double> sampleWidth_;
  struct SampleIndex;  // the sample bucketed once (adaptive only)
  std::shared_ptr<const SampleIndex> sampleIndex_;
};

}  // namespace nuld
