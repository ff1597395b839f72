#include "sampler/sequences/sobol.h"

#include <array>
#include <bit>
#include <stdexcept>
#include <string>

namespace nuld {
namespace {

// Joe & Kuo, "Constructing Sobol sequences with better two-dimensional
// projections" (2008): per dimension the degree s of the primitive polynomial,
// its interior coefficients a, and the initial direction integers m_1..m_s.
struct DirectionEntry {
  std::uint32_t s, a;
  std::array<std::uint32_t, 7> m;
};

constexpr std::array<DirectionEntry, kSobolMaxDimensions - 1> kJoeKuo = {{
    {1, 0, {1}},
    {2, 1, {1, 3}},
    {3, 1, {1, 3, 1}},
    {3, 2, {1, 1, 1}},
    {4, 1, {1, 1, 3, 3}},
    {4, 4, {1, 3, 5, 13}},
    {5, 2, {1, 1, 5, 5, 17}},
    {5, 4, {1, 1, 5, 5, 5}},
    {5, 7, {1, 1, 7, 11, 19}},
    {5, 11, {1, 1, 5, 1, 1}},
    {5, 13, {1, 1, 1, 3, 11}},
    {5, 14, {1, 3, 5, 5, 31}},
    {6, 1, {1, 3, 3, 9, 7, 49}},
    {6, 13, {1, 1, 1, 15, 21, 21}},
    {6, 16, {1, 3, 1, 13, 27, 49}},
    {6, 19, {1, 1, 1, 15, 7, 5}},
    {6, 22, {1, 3, 1, 15, 13, 25}},
    {6, 25, {1, 1, 5, 5, 19, 61}},
    {7, 1, {1, 3, 7, 11, 23, 15, 103}},
    {7, 4, {1, 3, 7, 13, 13, 15, 69}},
    {7, 7, {1, 1, 3, 13, 7, 35, 63}},
    {7, 8, {1, 3, 5, 9, 1, 25, 53}},
    {7, 14, {1, 3, 1, 13, 9, 35, 107}},
    {7, 19, {1, 3, 1, 5, 27, 61, 31}},
}};

using DirectionNumbers = std::array<std::uint32_t, 32>;  // V_1..V_32, MSB-aligned

constexpr DirectionNumbers directionNumbers(std::uint32_t dim) {
  DirectionNumbers v{};
  if (dim == 0) {
    for (int k = 0; k < 32; ++k) v[k] = 1u << (31 - k);
    return v;
  }
  const DirectionEntry &e = kJoeKuo[dim - 1];
  const std::uint32_t s = e.s;
  for (std::uint32_t k = 0; k < s && k < 32; ++k) v[k] = e.m[k] << (31 - k);
  for (std::uint32_t k = s; k < 32; ++k) {
    std::uint32_t x = v[k - s] ^ (v[k - s] >> s);
    for (std::uint32_t l = 1; l < s; ++l)
      if ((e.a >> (s - 1 - l)) & 1u) x ^= v[k - l];
    v[k] = x;
  }
  return v;
}

constexpr auto kDirections = [] {
  std::array<DirectionNumbers, kSobolMaxDimensions> all{};
  for (std::uint32_t d = 0; d < kSobolMaxDimensions; ++d) all[d] = directionNumbers(d);
  return all;
}();

}  // namespace

std::uint32_t sobolBits(std::uint64_t index, std::uint32_t dim) {
  if (dim >= kSobolMaxDimensions)
    throw std::out_of_range("Sobol: dimension " + std::to_string(dim) + " exceeds the " +
                            std::to_string(kSobolMaxDimensions) + " tabulated dimensions");
  if (index >> 32)
    throw std::out_of_range("Sobol: index " + std::to_string(index) + " needs more than 32 bits");
  std::uint64_t gray = index ^ (index >> 1);
  const DirectionNumbers &v = kDirections[dim];
  std::uint32_t x = 0;
  for (int k = 0; gray; ++k, gray >>= 1)
    if (gray & 1u) x ^= v[k];
  return x;
}

void sobolRun(std::uint32_t dim, std::span<std::uint32_t> out) {
  if (out.empty()) return;
  sobolBits(out.size() - 1, dim);  // the same range checks
  const DirectionNumbers &v = kDirections[dim];
  std::uint32_t x = 0;
  out[0] = 0;
  for (std::size_t i = 1; i < out.size(); ++i) out[i] = x ^= v[std::countr_zero(i)];
}

}  // namespace nuld
