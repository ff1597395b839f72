#pragma once
// Value types shared by the whole sampler module: a 2D point, an axis-aligned
// box in the unit square, and a point set that may hold several instances.

#include <cmath>
#include <cstddef>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "sampler/enum_names.h"

namespace nuld {

struct Point2 {
  double x = 0, y = 0;

  double operator[](int k) const { return k == 0 ? x : y; }
  double &operator[](int k) { return k == 0 ? x : y; }
  friend Point2 operator+(Point2 a, Point2 b) { return {a.x + b.x, a.y + b.y}; }
  friend Point2 operator-(Point2 a, Point2 b) { return {a.x - b.x, a.y - b.y}; }
  friend Point2 operator*(double s, Point2 a) { return {s * a.x, s * a.y}; }
  friend bool operator==(Point2 a, Point2 b) = default;
};

inline bool isFinite(Point2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }
// In the closed unit square, where every point set and target lives; false
// for NaN and infinite coordinates.
inline bool inUnitSquare(Point2 p) { return p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1; }

// t modulo 1 in [0, 1): a toroidal wrap. A tiny negative t would round to
// exactly 1, which is folded to 0.
inline double wrapUnit(double t) {
  t -= std::floor(t);
  return t < 1 ? t : 0.0;
}

// A closed box [lo.x, hi.x] x [lo.y, hi.y]. Boxes with lo > hi are empty.
struct Box2 {
  Point2 lo, hi;

  double area() const { return std::max(0.0, hi.x - lo.x) * std::max(0.0, hi.y - lo.y); }
  bool contains(Point2 p) const { return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y; }
  // Clipped to the unit square.
  Box2 clipped() const {
    return {{std::max(lo.x, 0.0), std::max(lo.y, 0.0)}, {std::min(hi.x, 1.0), std::min(hi.y, 1.0)}};
  }
};

// Where the points of a set live. The sphere is parameterized by the
// cylindrical equal-area map (u,v) -> (phi = 2 pi u, cos theta = 1 - 2v);
// the hemisphere is its v in [0, 1/2] half (docs/architecture.md, "Domains").
enum class Domain { Square, Sphere, Hemisphere };

inline constexpr auto kDomainNames = enumTable<Domain>(
    "domain",
    {{"square", Domain::Square}, {"sphere", Domain::Sphere}, {"hemisphere", Domain::Hemisphere}});
constexpr const auto &enumNames(Domain) { return kDomainNames; }

// Maps a point into its domain. On the sphere (and hemisphere) longitude is
// periodic and a point past a pole comes back on the other side, (u + 1/2,
// -v) or (u + 1/2, 2 - v), as often as it crossed one; `vSign` receives
// dv_out/dv_in (+1 or -1). On the square the point is clamped to [0, 1)^2.
// The direct optimizer's unmapped sphere points and the neural generator's
// unmapped outputs both land through it.
Point2 wrapToDomain(Point2 p, Domain domain, double *vSign = nullptr);

// A point set: `instances` sets of `n` points each, stored one after another.
// Metadata is free-form text carried through files (target, settings, metrics).
struct PointSet {
  std::size_t n = 0;
  std::vector<Point2> points;  // instances() * n points
  std::map<std::string, std::string> metadata;

  std::size_t instances() const { return n == 0 ? 0 : points.size() / n; }
  std::span<const Point2> instance(std::size_t k) const {
    return std::span<const Point2>(points).subspan(k * n, n);
  }
  std::span<Point2> instance(std::size_t k) { return std::span<Point2>(points).subspan(k * n, n); }
};

}  // namespace nuld
