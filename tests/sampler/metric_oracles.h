#pragma once
// Shared oracles of the metric tests (metrics_*_test.cpp): test-side point
// sets and exact L2 discrepancies. They share no code with the library: the
// L2 discrepancies are integrated exactly cell by cell (the local discrepancy
// is a polynomial between consecutive point coordinates).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <random>
#include <span>
#include <vector>

#include "sampler/point.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/target.h"

namespace nuld::test {

// Test-side random numbers, independent of the library's generators.
class TestRng {
 public:
  explicit TestRng(std::uint64_t seed) : gen_(seed) {}
  double uniform() { return double(gen_() >> 11) * 0x1.0p-53; }
  int uniformInt(int n) { return int(gen_() % std::uint64_t(n)); }

 private:
  std::mt19937_64 gen_;
};

// n independent uniform points from TestRng(seed).
std::vector<Point2> randomPoints(std::size_t n, std::uint64_t seed);

// Points on the grid {0, 1/8, ..., 1}: many ties in x and y, duplicates,
// points at 0 and at exactly 1.
std::vector<Point2> latticePoints(std::size_t n, std::uint64_t seed);

// The first n points of instance 0 of the Sobol sequence, scrambled so.
std::vector<Point2> sequencePoints(Scramble scramble, std::uint64_t seed, std::size_t n);

// The box spanned by corner (cx, cy) in {0,1}^2 and (a, b):
// [0,a] or [a,1] in x, [0,b] or [b,1] in y.
Box2 cornerBox(int cx, int cy, double a, double b);

// The measure mu of cornerBox(cx, cy, a, b) that the point counts are
// compared with.
using CornerMeasure = std::function<double(int cx, int cy, double a, double b)>;

// The area of cornerBox(cx, cy, a, b): the uniform measure.
double uniformCornerMeasure(int cx, int cy, double a, double b);

// L2-star (anchored at the origin) and L2asd (all four corners) discrepancy
// of p against mu, integrated exactly cell by cell. mu must be a polynomial
// of degree <= 2 in each of a and b between consecutive point coordinates
// and the extra breakpoints xBreaks, yBreaks (uniform and bilinear targets;
// step and grid targets with their jumps as breakpoints).
double exactL2Star(std::span<const Point2> p, const CornerMeasure &mu = uniformCornerMeasure,
                   const std::vector<double> &xBreaks = {},
                   const std::vector<double> &yBreaks = {});
double exactL2asd(std::span<const Point2> p, const CornerMeasure &mu = uniformCornerMeasure,
                  const std::vector<double> &xBreaks = {}, const std::vector<double> &yBreaks = {});

// The points u mapped by the target's inverse.
std::vector<Point2> mapped(std::span<const Point2> u, const Target &t);

}  // namespace nuld::test
