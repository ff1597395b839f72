#pragma once
// Angles in turns (2 pi t radians), the unit every sampling routine draws its
// azimuth in (phi = 2 pi u) and the lat-long map indexes by.
//  - sinCosTurns: the range reduction is exact (4t minus the nearest
//    integer) and r carries its rounding in a second double, so Taylor
//    polynomials on |r| <= pi/4 give both values within an ulp (with or
//    without fused multiply-adds), far cheaper than the C library's sin and cos, which must
//    handle an arbitrary argument; sampling calls them for every direction
//    (figures: tools/experiments/implementation_notes.md).
//  - atan2Turns: the octant reduction, then atan(a) = atan(c) + atan(t) with c
//    the nearest sixteenth, |t| <= 1/32 and a 15th-degree Taylor polynomial:
//    about 1e-16 turns, at about half the C library's atan2 time.

#include <array>
#include <cmath>
#include <numbers>

namespace nuld {

struct SinCos {
  double sin, cos;
};

// The rounding error of a * b: a * b - round(a * b), exactly. One fused
// multiply-add where the target has it, else Dekker's split product.
inline double productError(double a, double b, double product) {
#ifdef __FMA__
  return std::fma(a, b, -product);
#else
  constexpr double kSplit = 134217729.0;  // 2^27 + 1
  const double ca = kSplit * a, ah = ca - (ca - a), al = a - ah;
  const double cb = kSplit * b, bh = cb - (cb - b), bl = b - bh;
  return ((ah * bh - product) + ah * bl + al * bh) + al * bl;
#endif
}

inline SinCos sinCosTurns(double t) {
  const double q = std::nearbyint(4 * t);  // quarter turns
  // r = (4t - q) pi/2 as an unevaluated sum r + rLow: the subtraction is
  // exact, and carrying the product's rounding and pi/2's own keeps sin r
  // within an ulp with or without fused multiply-adds.
  constexpr double kHalfPi = std::numbers::pi / 2;
  constexpr double kHalfPiLow = 6.123233995736766e-17;  // pi/2 - kHalfPi
  const double d = 4 * t - q, r = d * kHalfPi;
  const double rLow = productError(d, kHalfPi, r) + d * kHalfPiLow, r2 = r * r;
  // sin r = r (1 - r^2/3! + ... + r^16/17!), cos r = 1 - r^2/2! + ... - r^18/18!:
  // the first omitted terms are below 1e-19 for |r| <= pi/4.
  double ps = 1.0 / 355687428096000.0;
  ps = ps * r2 - 1.0 / 1307674368000.0;
  ps = ps * r2 + 1.0 / 6227020800.0;
  ps = ps * r2 - 1.0 / 39916800.0;
  ps = ps * r2 + 1.0 / 362880.0;
  ps = ps * r2 - 1.0 / 5040.0;
  ps = ps * r2 + 1.0 / 120.0;
  ps = ps * r2 - 1.0 / 6.0;
  const double sinR = r + (rLow + r * r2 * ps);
  double pc = -1.0 / 6402373705728000.0;
  pc = pc * r2 + 1.0 / 20922789888000.0;
  pc = pc * r2 - 1.0 / 87178291200.0;
  pc = pc * r2 + 1.0 / 479001600.0;
  pc = pc * r2 - 1.0 / 3628800.0;
  pc = pc * r2 + 1.0 / 40320.0;
  pc = pc * r2 - 1.0 / 720.0;
  pc = pc * r2 + 1.0 / 24.0;
  // cos r = 1 - r^2/2 + r^4 pc with 1 - r^2/2 in two parts (fdlibm's
  // kernel): w = 1 - h rounded, and what that rounding, r^2's and rLow's
  // share of r^2 left out.
  const double h = 0.5 * r2, w = 1 - h;
  const double hLow = 0.5 * productError(r, r, r2) + r * rLow;
  const double cosR = w + ((((1 - w) - h) - hLow) + r2 * r2 * pc);
  // Turn by q quarter turns: (sin, cos) -> (cos, -sin) per quarter.
  const long k = static_cast<long>(q) & 3;
  const double a = (k & 1) ? cosR : sinR, b = (k & 1) ? sinR : cosR;
  return {(k & 2) ? -a : a, ((k + 1) & 2) ? -b : b};
}

// atan(j / 16) for j = 0..16, the centres of atan2Turns' reduction.
inline const std::array<double, 17> kAtanSixteenths = [] {
  std::array<double, 17> t{};
  for (int j = 0; j <= 16; ++j) t[j] = std::atan(j / 16.0);
  return t;
}();

// atan2(y, x) / (2 pi) in [0, 1] (1 only by rounding, for y just below 0):
// the azimuth of (x, y) in turns; 0 for x = y = 0.
inline double atan2Turns(double y, double x) {
  const double ax = std::fabs(x), ay = std::fabs(y);
  const bool steep = ay > ax;
  const double num = steep ? ax : ay, den = steep ? ay : ax;
  if (!(den > 0)) return 0;
  const double a = num / den;  // in [0, 1]: the first octant
  const double j = std::nearbyint(16 * a), c = j * (1.0 / 16);
  const double t = (a - c) / (1 + a * c), t2 = t * t;  // atan a = atan c + atan t
  double p = -1.0 / 15;
  p = p * t2 + 1.0 / 13;
  p = p * t2 - 1.0 / 11;
  p = p * t2 + 1.0 / 9;
  p = p * t2 - 1.0 / 7;
  p = p * t2 + 1.0 / 5;
  p = p * t2 - 1.0 / 3;
  double turns = (kAtanSixteenths[int(j)] + (t + t * t2 * p)) * (0.5 / std::numbers::pi);
  // Unfold the octant with selects (the branches would be unpredictable).
  turns = steep ? 0.25 - turns : turns;
  turns = x < 0 ? 0.5 - turns : turns;
  return y < 0 && turns > 0 ? 1 - turns : turns;
}

}  // namespace nuld
