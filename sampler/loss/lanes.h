#pragma once
// A vector of doubles for the soft box loss's inner loops, written with the
// GCC/Clang vector extensions: eight lanes in one AVX-512 register where
// the build targets it (-march=native on this project's machines), four
// with AVX, two otherwise, with the same arithmetic on every lane.
// Auto-vectorizing the scalar loop had left a scalar reduction and a
// Horner-bound exp per pair (tools/experiments/optimizer_speed.md).

#include <bit>
#include <cstdint>
#include <cstring>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace nuld::lanes {

#if defined(__AVX512F__)
inline constexpr int kWidth = 8;
#elif defined(__AVX__)
inline constexpr int kWidth = 4;
#else
inline constexpr int kWidth = 2;
#endif
using Doubles = double __attribute__((vector_size(8 * kWidth)));
using Mask = std::int64_t __attribute__((vector_size(8 * kWidth)));  // all ones or zero per lane

// Every lane x. (Doubles{} + x would turn -0.0 into +0.0.)
inline Doubles broadcast(double x) {
  Doubles v;
  for (int j = 0; j < kWidth; ++j) v[j] = x;
  return v;
}
// 0, 1, ..., kWidth - 1.
inline Mask laneIndex() {
  Mask v;
  for (int j = 0; j < kWidth; ++j) v[j] = j;
  return v;
}
inline Doubles load(const double *p) {
  Doubles v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline Mask loadMask(const std::int64_t *p) {
  Mask v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store(double *p, Doubles v) { std::memcpy(p, &v, sizeof v); }

// table[index[j]] in lane j, for a table of 8 and indices in [0, 8): one
// permutation where 8 lanes fill a register, lane by lane elsewhere.
inline Doubles lookup8(const double *table, Mask index) {
#if !defined(__clang__)
  if constexpr (kWidth == 8) return __builtin_shuffle(load(table), index);
#endif
  Doubles out;
  for (int j = 0; j < kWidth; ++j) out[j] = table[index[j] & 7];
  return out;
}

// std::min's rule, lane by lane: b when b < a, else a.
inline Doubles min(Doubles a, Doubles b) { return b < a ? b : a; }
// std::max's rule: b when a < b, else a.
inline Doubles max(Doubles a, Doubles b) { return a < b ? b : a; }
inline Doubles abs(Doubles a) {
  constexpr std::int64_t kMagnitude = 0x7fff'ffff'ffff'ffff;  // every bit but the sign
  return std::bit_cast<Doubles>(std::bit_cast<Mask>(a) & kMagnitude);
}
// The lanes' sum, pairwise in a fixed order.
inline double sum(Doubles v) {
  double part[kWidth];
  for (int j = 0; j < kWidth; ++j) part[j] = v[j];
  for (int width = kWidth / 2; width > 0; width /= 2)
    for (int j = 0; j < width; ++j) part[j] = part[2 * j] + part[2 * j + 1];
  return part[0];
}
// Lanes [0, n) set: every lane once n >= kWidth.
inline Mask firstLanes(std::int64_t n) { return laneIndex() < n; }

// Writes the lanes of v that m selects to out[0, count), in lane order, and
// returns count; out must hold kWidth values (the rest are overwritten).
inline int compress(Mask m, Doubles v, double *out) {
#if defined(__AVX512F__)
  const __mmask8 bits =
      _mm512_test_epi64_mask(std::bit_cast<__m512i>(m), std::bit_cast<__m512i>(m));
  _mm512_storeu_pd(out, _mm512_maskz_compress_pd(bits, std::bit_cast<__m512d>(v)));
  return std::popcount(unsigned(bits));
#else
  int count = 0;
  for (int j = 0; j < kWidth; ++j)
    if (m[j]) out[count++] = v[j];
  return count;
#endif
}

// exp(x), lane by lane, for x clamped to [-700, 700] (beyond, the result is
// that of the bound): Cody-Waite range reduction x = n ln2 + r with
// |r| <= ln2/2, a degree-12 Taylor polynomial for e^r, and 2^n assembled in
// the exponent bits. Relative error below 1e-15 (tests/sampler/lanes_test.cpp).
// No call and no branch, so it stays in vector registers.
inline Doubles exp(Doubles x) {
  x = x < -700.0 ? broadcast(-700.0) : x;
  x = x > 700.0 ? broadcast(700.0) : x;
  constexpr double kLog2e = 1.4426950408889634;
  // ln2 split so that n * kLn2Hi is exact for |n| < 2^21 (kLn2Hi has 32
  // significant bits, fdlibm's split): the reduction needs no fused
  // multiply-add to be exact.
  constexpr double kLn2Hi = 6.93147180369123816490e-01;
  constexpr double kLn2Lo = 1.90821492927058770002e-10;  // ln2 - kLn2Hi
  constexpr double kShift = 6755399441055744.0;          // 1.5 * 2^52: rounds to integer
  const Doubles t = x * kLog2e + kShift;
  const Doubles n = t - kShift;  // round(x log2 e)
  const Doubles r = (x - n * kLn2Hi) - n * kLn2Lo;
  // Estrin's scheme: four multiply-adds deep instead of Horner's thirteen.
  const Doubles r2 = r * r, r4 = r2 * r2, r8 = r4 * r4;
  const Doubles q0 = 1.0 + r, q1 = 0.5 + r * (1.0 / 6.0), q2 = 1.0 / 24.0 + r * (1.0 / 120.0);
  const Doubles q3 = 1.0 / 720.0 + r * (1.0 / 5040.0), q4 = 1.0 / 40320.0 + r * (1.0 / 362880.0);
  const Doubles q5 = 1.0 / 3628800.0 + r * (1.0 / 39916800.0);
  const Doubles s0 = q0 + r2 * q1, s1 = q2 + r2 * q3, s2 = q4 + r2 * q5;
  const Doubles t0 = s0 + r4 * s1, t1 = s2 + r4 * (1.0 / 479001600.0);
  const Doubles p = t0 + r8 * t1;
  // The low bits of t hold n (two's complement); move them into the exponent.
  const Mask bits = (std::bit_cast<Mask>(t) + 1023) << 52;
  return p * std::bit_cast<Doubles>(bits);
}

}  // namespace nuld::lanes
