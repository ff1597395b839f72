#pragma once
// The Sobol sequence in base 2 with Joe & Kuo's direction numbers
// ("new-joe-kuo-6.21201", first 25 dimensions; dimension 0 is van der Corput).
//
// Index convention: index 0 is included (it is the origin), and points are
// produced in Gray-code order, as in Joe & Kuo's reference program, so the
// first points match published tables. Any prefix of length 2^m is a (t,m,s)-net.

#include <cstdint>
#include <span>

namespace nuld {

inline constexpr std::uint32_t kSobolMaxDimensions = 25;

// The 32-bit Sobol integer of point `index` in dimension `dim`.
std::uint32_t sobolBits(std::uint64_t index, std::uint32_t dim);

// sobolBits of indices 0..out.size()-1 of `dim`, by the Gray-code recurrence
// (point i = point i-1 XOR the direction number of i's lowest set bit): one
// XOR per point instead of a loop over the index's bits.
void sobolRun(std::uint32_t dim, std::span<std::uint32_t> out);

// The same as a double in [0, 1).
inline double sobolSample(std::uint64_t index, std::uint32_t dim) {
  return sobolBits(index, dim) * 0x1.0p-32;
}

}  // namespace nuld
