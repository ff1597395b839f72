#pragma once
// An infinitely distant light from a lat-long HDR map (row 0 = zenith, +Y up;
// column u = 0 faces -Z, u = 1/4 faces +X), scaled and rotated about +Y.
//
// Sampling is the sampler module's `envmap:` target: the map's luminance as a
// piecewise-constant density whose rows are re-gridded to the equal-area v,
// which is exactly pbrt's luminance x sin(theta) distribution with sin(theta)
// integrated over each row. Because the light samples *through the target*, a
// backend may hand over points already distributed by that target (optimized
// or neural sets) and the light uses them with the same pdf.

#include <memory>
#include <optional>
#include <string>

#include "materials/rgb.h"
#include "materials/vec3.h"
#include "sampler/io/image_io.h"
#include "sampler/targets/grid_target.h"

namespace nuld {

struct LightSample {
  Vec3 wi;       // world direction towards the light
  Rgb radiance;  // Le(wi)
  double pdf{};  // per unit solid angle
};

class EnvironmentLight {
 public:
  // `source` names the map in errors and in the target's spec (envmap:SOURCE).
  EnvironmentLight(Image latlong, double scale, double rotationDegrees, std::string source);

  Rgb radiance(Vec3 worldDirection) const;
  // Density per unit solid angle of sampleTarget() / sample(); 0 for a black map.
  double pdf(Vec3 worldDirection) const;
  // Both at once (one cell lookup): what a path that escapes needs.
  Rgb radiance(Vec3 worldDirection, double &pdf) const;

  // u uniform in [0,1)^2 -> a direction by inverse CDF; nullopt for a black map.
  std::optional<LightSample> sample(Point2 u) const;
  // x already distributed by target() -> the direction it stands for.
  std::optional<LightSample> sampleTarget(Point2 x) const;

  // The sampling density on the equal-area square; null when the map is black.
  const GridTarget *target() const { return target_.get(); }
  const std::string &source() const { return source_; }
  int width() const { return image_.width; }
  int height() const { return image_.height; }

  // Map-local direction (z = the map's up) <-> world direction.
  Vec3 toWorld(Vec3 local) const;
  Vec3 toLocal(Vec3 world) const;

 private:
  Rgb texel(GridTarget::Cell c) const {
    return {image_.at(c.i, c.j, 0), image_.at(c.i, c.j, 1), image_.at(c.i, c.j, 2)};
  }
  std::optional<LightSample> sampleCell(Point2 x, GridTarget::Cell c) const;

  Image image_;  // RGB, non-negative, scale applied
  std::unique_ptr<GridTarget> target_;
  double cosRot_, sinRot_;
  std::string source_;
};

}  // namespace nuld
