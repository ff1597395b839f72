#pragma once
// Value types for 3D directions and positions, shared by materials and the
// renderer. Double precision throughout: shading is cheap next to tracing,
// and it keeps grazing-angle terms (cos theta near 0) free of cancellation.

#include <algorithm>
#include <cmath>

namespace nuld {

struct Vec3 {
  double x = 0, y = 0, z = 0;

  double operator[](int k) const { return k == 0 ? x : (k == 1 ? y : z); }
  double &operator[](int k) { return k == 0 ? x : (k == 1 ? y : z); }
  Vec3 operator-() const { return {-x, -y, -z}; }
  Vec3 &operator+=(Vec3 b) {
    x += b.x;
    y += b.y;
    z += b.z;
    return *this;
  }
  friend Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
  friend Vec3 operator*(Vec3 a, double s) { return {s * a.x, s * a.y, s * a.z}; }
  friend Vec3 operator/(Vec3 a, double s) { return {a.x / s, a.y / s, a.z / s}; }
  friend bool operator==(Vec3 a, Vec3 b) = default;
};

inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double lengthSquared(Vec3 a) { return dot(a, a); }
inline double length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(Vec3 a) { return a / length(a); }
inline bool isFinite(Vec3 a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
inline Vec3 min(Vec3 a, Vec3 b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline Vec3 max(Vec3 a, Vec3 b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
// The reflection of `w` about the normal `n` (both unit, pointing away).
inline Vec3 reflect(Vec3 w, Vec3 n) { return 2 * dot(w, n) * n - w; }

}  // namespace nuld
