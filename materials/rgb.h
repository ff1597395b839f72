#pragma once
// Linear RGB radiance and reflectance (Rec. 709 primaries).

#include <algorithm>
#include <cmath>

#include "sampler/io/image_io.h"

namespace nuld {

struct Rgb {
  double r = 0, g = 0, b = 0;

  static Rgb grey(double v) { return {v, v, v}; }
  Rgb &operator+=(Rgb o) {
    r += o.r;
    g += o.g;
    b += o.b;
    return *this;
  }
  Rgb &operator*=(Rgb o) {
    r *= o.r;
    g *= o.g;
    b *= o.b;
    return *this;
  }
  Rgb &operator*=(double s) {
    r *= s;
    g *= s;
    b *= s;
    return *this;
  }
  friend Rgb operator+(Rgb a, Rgb o) { return {a.r + o.r, a.g + o.g, a.b + o.b}; }
  friend Rgb operator-(Rgb a, Rgb o) { return {a.r - o.r, a.g - o.g, a.b - o.b}; }
  friend Rgb operator*(Rgb a, Rgb o) { return {a.r * o.r, a.g * o.g, a.b * o.b}; }
  friend Rgb operator*(double s, Rgb a) { return {s * a.r, s * a.g, s * a.b}; }
  friend Rgb operator*(Rgb a, double s) { return {s * a.r, s * a.g, s * a.b}; }
  friend Rgb operator/(Rgb a, double s) { return {a.r / s, a.g / s, a.b / s}; }
  friend bool operator==(Rgb a, Rgb b) = default;

  double luminance() const { return rec709Luminance(r, g, b); }
  double maxComponent() const { return std::max({r, g, b}); }
  bool isBlack() const { return r == 0 && g == 0 && b == 0; }
  bool isFinite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
};

// Linear interpolation a + t (b - a).
inline Rgb lerp(double t, Rgb a, Rgb b) { return (1 - t) * a + t * b; }

}  // namespace nuld
