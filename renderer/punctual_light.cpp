#include "renderer/punctual_light.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace nuld {

namespace {

constexpr double kPi = std::numbers::pi;

Vec3 unitDirection(Vec3 d, const char *what) {
  const double len = length(d);
  if (!(len > 0) || !std::isfinite(len))
    throw std::invalid_argument(std::string("punctual light: ") + what + " is zero or not finite");
  return d / len;
}

void checkValue(Rgb v, const char *what) {
  if (!v.isFinite() || v.r < 0 || v.g < 0 || v.b < 0)
    throw std::invalid_argument(std::string("punctual light: ") + what +
                                " must be finite and >= 0");
}

void checkRange(double range) {
  if (!(range > 0)) throw std::invalid_argument("punctual light: range must be > 0");
}

}  // namespace

PunctualLight PunctualLight::point(Vec3 position, Rgb intensity, double range) {
  checkValue(intensity, "intensity");
  checkRange(range);
  PunctualLight l;
  l.kind_ = Kind::Point;
  l.position_ = position;
  l.value_ = intensity;
  l.range_ = range;
  return l;
}

PunctualLight PunctualLight::spot(Vec3 position, Vec3 direction, Rgb intensity, double innerAngle,
                                  double outerAngle, double range) {
  checkValue(intensity, "intensity");
  checkRange(range);
  if (!(innerAngle >= 0 && innerAngle < outerAngle && outerAngle <= kPi / 2))
    throw std::invalid_argument(
        "punctual light: a spot's cone angles must satisfy 0 <= inner < outer <= pi/2");
  PunctualLight l = point(position, intensity, range);
  l.kind_ = Kind::Spot;
  l.direction_ = unitDirection(direction, "the spot's direction");
  l.cosInner_ = std::cos(innerAngle);
  l.cosOuter_ = std::cos(outerAngle);
  return l;
}

PunctualLight PunctualLight::directional(Vec3 direction, Rgb irradiance) {
  checkValue(irradiance, "irradiance");
  PunctualLight l;
  l.kind_ = Kind::Directional;
  l.direction_ = unitDirection(direction, "the direction");
  l.value_ = irradiance;
  return l;
}

double PunctualLight::power(double sceneRadius) const {
  const double y = value_.luminance();
  switch (kind_) {
    case Kind::Point: return 4 * kPi * y;
    case Kind::Spot: return 2 * kPi * y * (1 - 0.5 * (cosInner_ + cosOuter_));
    case Kind::Directional:
    default: return kPi * sceneRadius * sceneRadius * y;
  }
}

std::optional<AreaLightSample> PunctualLight::sample(Vec3 p) const {
  if (kind_ == Kind::Directional)
    return AreaLightSample{-direction_, std::numeric_limits<double>::infinity(), value_, 1.0, true};
  const Vec3 toLight = position_ - p;
  const double d2 = dot(toLight, toLight);
  const double d = std::sqrt(d2);
  if (!(d > 0) || !std::isfinite(d2) || d > range_) return std::nullopt;
  const Vec3 wi = toLight / d;
  double falloff = 1;
  if (kind_ == Kind::Spot) {
    // glTF's spot falloff: a ramp in cos from the outer to the inner angle,
    // squared.
    const double cd = dot(direction_, -wi);
    const double t = std::clamp((cd - cosOuter_) / std::max(1e-3, cosInner_ - cosOuter_), 0.0, 1.0);
    falloff = t * t;
    if (falloff == 0) return std::nullopt;
  }
  return AreaLightSample{wi, d, (falloff / d2) * value_, 1.0, true};
}

void PunctualLight::hashContent(ContentHash &h) const {
  h.add("punctual").add(std::uint64_t(kind_));
  for (const Vec3 v : {position_, direction_}) h.add(v.x).add(v.y).add(v.z);
  h.add(value_.r).add(value_.g).add(value_.b).add(cosInner_).add(cosOuter_).add(range_);
}

}  // namespace nuld
