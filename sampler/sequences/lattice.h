#pragma once
// Rank-1 lattices: point i of N is (i / N, frac(i g / N)), the lattice of
// the integer vectors (1, g) and (0, N) scaled by 1 / N. Randomized by a
// Cranley-Patterson (toroidal) shift, which keeps it a lattice on the torus
// and makes every point uniform; optionally followed by the baker's (tent)
// transform, which lets a lattice rule integrate smooth integrands that are
// not periodic (Hickernell 2002).

#include <cstddef>
#include <cstdint>
#include <span>

#include "sampler/point.h"

namespace nuld {

// Sizes up to this get the searched generator; larger ones the Fibonacci rule.
inline constexpr std::uint32_t kMaxSearchedLattice = 65536;

// The squared length of the shortest nonzero vector of the integer lattice
// spanned by (1, g) and (0, n), by Gauss-Lagrange reduction (O(log n)).
std::uint64_t latticeShortestVector2(std::uint32_t n, std::uint32_t g);

// The generator g of the N-point lattice. N <= kMaxSearchedLattice: the g in
// [1, N) coprime with N whose lattice has the longest shortest vector (the
// points' smallest toroidal distance, times N), the smallest such g on ties;
// searched once per N (O(N log N), 3 ms at N = 65536) and kept, lock-free,
// for every thread. Larger N: goldenRatioGenerator(N). N = 1: 0; N = 2: 1.
//
// Coprime, so that the lattice is projection-regular: each coordinate takes
// all N values i / N, as each coordinate of a (0,2)-net has one point in
// each of N intervals. Without that condition a square N wins with a
// sheared square grid (N = 16: g = 4, whose y takes 4 values), which
// integrates anything that varies along y like 4 samples.
//
// For a Fibonacci N = F(k) the search does not give the Fibonacci lattice
// (g = F(k-2)): that lattice's reduced basis is close to a square (shortest
// vector N or 0.89 N, squared), while the best-separated rank-1 lattices
// approach the hexagonal one (2 / sqrt(3) N = 1.155 N; e.g. 146 against 128
// at N = 144, 52730 against 41472 at N = 46368). Only equal spacing is
// sought here; the Fibonacci lattice is goldenRatioGenerator's.
std::uint32_t latticeGenerator(std::size_t n);

// The golden-ratio choice: round(N / phi^2), moved to the nearest g coprime
// with N (ties: the smaller); the Fibonacci lattice g = F(k-2) for N = F(k).
std::uint32_t goldenRatioGenerator(std::uint32_t n);

// The unshifted lattice of N = out.size() points in index order.
void rank1Lattice(std::span<Point2> out);

// The lattice of N = out.size() points under the toroidal shift of `seed`,
// in the random order of `seed` (a renderer that pairs dimensions by index
// then pairs them at random). Every point is uniform on [0, 1)^2.
void latticeSet(std::uint64_t seed, std::span<Point2> out);

// latticeSet's points, each coordinate then folded by the baker's transform
// x -> 1 - |2x - 1| (kept below 1). The fold keeps every point uniform and
// makes a smooth integrand's composition periodic: a shifted lattice
// integrates f(fold(x)) as it would a periodic function.
void latticeBakerSet(std::uint64_t seed, std::span<Point2> out);

// The baker's transform of one coordinate, in [0, 1).
double bakerFold(double x);

}  // namespace nuld
