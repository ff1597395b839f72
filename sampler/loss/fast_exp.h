#pragma once
// exp(x) for x <= 0 (clamped at -700, beyond which it returns ~1e-304) without branches or calls,
// so that compilers can vectorize loops over it (libm's exp is a scalar call). Cody-Waite range
// reduction x = n ln2 + r, |r| <= ln2/2, a degree-12 Taylor polynomial for
// e^r, and 2^n assembled in the exponent bits. Relative error < 1e-15.

#include <bit>
#include <cstdint>

namespace nuld {

inline double fastExpNonPositive(double x) {
  x = x < -700.0 ? -700.0 : x;
  constexpr double kLog2e = 1.4426950408889634;
  // ln2 split so that n * kLn2Hi is exact for |n| < 2^21 (kLn2Hi has 32
  // significant bits, fdlibm's split): the reduction needs no fused
  // multiply-add to be exact, so builds without FMA keep the accuracy.
  constexpr double kLn2Hi = 6.93147180369123816490e-01;
  constexpr double kLn2Lo = 1.90821492927058770002e-10;  // ln2 - kLn2Hi
  constexpr double kShift = 6755399441055744.0;          // 1.5 * 2^52: rounds to integer
  const double t = x * kLog2e + kShift;
  const double n = t - kShift;  // round(x log2 e)
  const double r = (x - n * kLn2Hi) - n * kLn2Lo;
  double p = 1.0 / 479001600.0;  // 1/12!
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  // The low bits of t hold n (two's complement); move them into the exponent.
  const std::int64_t bits = (std::bit_cast<std::int64_t>(t) + 1023) << 52;
  return p * std::bit_cast<double>(bits);
}

}  // namespace nuld
