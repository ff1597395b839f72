#pragma once
// Oracles of the classic sets' tests (stratified, pmj02, lattice, zsobol):
// a brute-force elementary-interval counter, a chi-square of binned values
// and the mean of a smooth integrand's estimates over seeds. They share no
// code with the generators they check.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "sampler/point.h"

namespace nuld::test {

// "" when the 2^m points have exactly one point in every elementary interval
// of area 2^-m of every shape 2^-a x 2^-(m-a) (counted cell by cell);
// otherwise the first shape and cell that does not.
std::string netFailure(std::span<const Point2> pts, int m);

// "" when every prefix of 2^j points (and, with `blocks`, every block of 2^j
// starting at a multiple of 2^j) is a (0, j, 2)-net, for 2^j <= pts.size();
// otherwise which one is not, and why.
std::string sequenceNetFailure(std::span<const Point2> pts, bool blocks);

// Pearson's chi-square of `counts` against equal expected counts.
double chiSquareUniform(std::span<const int> counts);
// Its critical value at p = 0.001 for `bins` - 1 degrees of freedom (bins in
// 2..64, Wilson-Hilferty), the threshold the tests use.
double chiSquareCritical(int bins);

// One set of N points from a seed, for the properties every generator shares.
using SetMaker = std::function<void(std::uint64_t seed, std::span<Point2> out)>;

// The mean over `seeds` seeds of the set's estimate of the integral of
// exp(x + y / 2) over the unit square, and its standard error.
struct MeanEstimate {
  double mean, standardError, exact;
};
MeanEstimate smoothIntegrandMean(const SetMaker &make, std::size_t n, int seeds);

}  // namespace nuld::test
