#pragma once
// Shared oracles of the sampling-target tests (targets_*_test.cpp): the list
// of targets under test with the hints the checks need, the images behind the
// image targets, and a chi-square test of a target's inverse map against box
// masses.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "sampler/io/image_io.h"
#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld::test {

inline constexpr double kPi = std::numbers::pi;

// ------------------------------------------------------------------ statistics

// The outcome of chiSquare below (not tests/common's ChiSquare: this one also
// counts the mapped points that fall where they must not).
struct MassChiSquare {
  double statistic = 0;
  int dof = 0;
  double pValue = 0;
  std::size_t outside = 0;       // mapped points outside [0,1]^2 (or not finite)
  std::size_t zeroDensity = 0;   // mapped points where the sampled target's pdf is 0
  std::size_t inEmptyCells = 0;  // points in cells the reference gives no mass
  double totalMass = 0;          // sum of the reference's cell masses
};

// Maps n uniform points through `sampled.invert`, bins them into bins x bins
// cells and compares with the cell masses of `reference` (pbrt-v4 / Mitsuba
// style: cells expected to hold fewer than 5 points are pooled).
MassChiSquare chiSquare(const Target &sampled, const Target &reference, int n, int bins,
                        std::uint64_t seed);

// --------------------------------------------------------------- the targets

struct Case {
  std::string name;
  std::shared_ptr<const Target> target;
  // Where the density may jump: lines x = const, y = const, and a curve
  // y = yCurve(x). Only hints for the quadrature, which is adaptive anyway.
  std::vector<double> xBreaks, yBreaks;
  std::function<double(double)> yCurve;
  // Id of the smooth piece of the inverse map containing a mapped point.
  std::function<int(Point2)> region = [](Point2) { return 0; };
  // The axis the inverse map samples first from its marginal (the grid
  // samples a row, then a column in it; the closed forms x, then y given x).
  int firstAxis = 0;
};

// Every target under test: the closed forms, two grids with zero rows and
// cells, and image and environment-map targets built from the images below.
const std::vector<Case> &allCases();

// The cells + 1 edges of `cells` equal cells on [0, 1].
std::vector<double> uniformEdges(int cells);

// A small lat-long environment map (RGB, 8 x 6) with a bright zenith pixel
// and some black pixels.
Image envmapImage();

// A small grey picture (5 x 3) with black pixels.
Image pictureImage();

}  // namespace nuld::test
