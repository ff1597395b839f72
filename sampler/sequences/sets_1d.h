#pragma once
// One-dimensional sets of N numbers, one per classic construction, for the
// 1D domains of a render (light choice, lobe choice, roulette:
// renderer/sample_layout.h). Each is its sequence's own 1D form, not a
// projection of its 2D set where the two differ: a 2D jittered grid of N
// points projects to only sqrt(N) strata, its 1D form has N.
//  - vanDerCorputSet: the first dimension of Sobol and of Halton (both are
//    van der Corput's base-2 radical inverse), Owen-scrambled: for N a power
//    of two one number in each interval [k/N, (k+1)/N).
//  - stratifiedSet1D: N jittered strata.
//  - latticeSet1D: the rank-1 lattice's first coordinate k/N under a random
//    shift (optionally folded by the baker's transform).
// Every number is uniform on [0, 1), and each set comes in a random order of
// its seed, so that a renderer pairing domains by index pairs them at random.

#include <cstdint>
#include <span>

namespace nuld {

void vanDerCorputSet(std::uint64_t seed, std::span<double> out);
void stratifiedSet1D(std::uint64_t seed, std::span<double> out);
void latticeSet1D(std::uint64_t seed, std::span<double> out, bool baker = false);

}  // namespace nuld
