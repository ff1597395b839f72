#pragma once
// Lights of no extent (glTF's KHR_lights_punctual; renderer/README.md,
// `punctual_light`): a point, a spot and a directional light. Each lights a
// point from one direction only, so next-event estimation draws it with
// probability 1 (AreaLightSample::delta) and no BSDF sample can meet it:
// the `bsdf` integrator does not see them.
//  - point: radiant intensity I (per steradian), I / d^2 at distance d;
//  - spot: the same within a cone, fading between the inner and the outer
//    angle by glTF's smooth falloff (the squared linear ramp in cos);
//  - directional: irradiance E on a surface facing it, from one direction.
// A point or spot light lights nothing beyond its `range` (infinite unless
// given), as glTF defines it.

#include <limits>
#include <optional>

#include "materials/rgb.h"
#include "materials/vec3.h"
#include "renderer/area_light.h"
#include "sampler/io/content_hash.h"

namespace nuld {

class PunctualLight {
 public:
  enum class Kind { Point, Spot, Directional };
  static constexpr double kNoRange = std::numeric_limits<double>::infinity();

  static PunctualLight point(Vec3 position, Rgb intensity, double range = kNoRange);
  // `direction` the cone's axis (the way the light shines), angles in
  // radians with 0 <= inner < outer <= pi / 2.
  static PunctualLight spot(Vec3 position, Vec3 direction, Rgb intensity, double innerAngle,
                            double outerAngle, double range = kNoRange);
  // `direction` the way the light travels.
  static PunctualLight directional(Vec3 direction, Rgb irradiance);

  Kind kind() const { return kind_; }
  Vec3 position() const { return position_; }
  // The luminance of the flux it emits, for the choice by power
  // (light_power.h): 4 pi I for a point, pbrt-v4's 2 pi I (1 - (cos inner +
  // cos outer) / 2) for a spot, pi r^2 E for a directional light over a
  // scene of radius r.
  double power(double sceneRadius) const;
  // The direction towards the light from `p` with the radiance-like factor
  // that makes f |cos| L / pdf the estimate (L = I falloff / d^2, or E) and
  // pdf 1; none where it lights nothing (outside the cone or the range).
  std::optional<AreaLightSample> sample(Vec3 p) const;
  void hashContent(ContentHash &h) const;

 private:
  PunctualLight() = default;
  Kind kind_ = Kind::Point;
  Vec3 position_, direction_;  // direction_: unit, the way the light shines
  Rgb value_;                  // intensity, or the directional light's irradiance
  double cosInner_ = 1, cosOuter_ = 0, range_ = kNoRange;
};

}  // namespace nuld
