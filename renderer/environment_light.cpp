#include "renderer/environment_light.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "materials/sphere_map.h"
#include "sampler/targets/image_targets.h"

namespace nuld {
namespace {

// Keeps three channels (grey maps are replicated), clamps negative values
// (colour conversions of HDR data produce them) and applies the scale.
Image toRgb(const Image &in, double scale, const std::string &source) {
  if (in.width <= 0 || in.height <= 0 || in.channels <= 0)
    throw std::invalid_argument(source + ": empty environment map");
  if (!(scale >= 0) || !std::isfinite(scale))
    throw std::invalid_argument(source + ": environment scale must be finite and >= 0");
  Image out{in.width, in.height, 3, std::vector<float>(std::size_t(in.width) * in.height * 3)};
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = in.at(x, y, in.channels >= 3 ? c : 0);
        if (!std::isfinite(v))
          throw std::invalid_argument(source + ": pixel (" + std::to_string(x) + ", " +
                                      std::to_string(y) + ") is not finite");
        out.at(x, y, c) = float(std::max(0.0f, v) * scale);
      }
  return out;
}

}  // namespace

EnvironmentLight::EnvironmentLight(Image latlong, double scale, double rotationDegrees,
                                   std::string source)
    : image_(toRgb(latlong, scale, source)), source_(std::move(source)) {
  const double rot = rotationDegrees * std::numbers::pi / 180;
  cosRot_ = std::cos(rot);
  sinRot_ = std::sin(rot);
  bool black = true;
  for (float v : image_.pixels) black = black && v == 0;
  // A black map emits nothing and has nothing to sample: no target.
  if (!black) target_ = makeEnvmapTarget(image_, source_);
}

// Map-local frame: z up (+Y world), phi = 0 towards -Z world, phi = pi/2
// towards +X world; then the map is turned about +Y by the rotation.
Vec3 EnvironmentLight::toWorld(Vec3 l) const {
  const Vec3 w{l.y, l.z, -l.x};
  return {cosRot_ * w.x + sinRot_ * w.z, w.y, -sinRot_ * w.x + cosRot_ * w.z};
}

Vec3 EnvironmentLight::toLocal(Vec3 w) const {
  const Vec3 r{cosRot_ * w.x - sinRot_ * w.z, w.y, sinRot_ * w.x + cosRot_ * w.z};
  return {-r.z, r.x, r.y};
}

// The map's pixels are the target's cells (columns uniform in u, rows at the
// equal-area images of the pixel rows), so one locate finds both the
// radiance and the density. A black map has no target: its radiance is 0.
Rgb EnvironmentLight::radiance(Vec3 w) const {
  double unused;
  return radiance(w, unused);
}

Rgb EnvironmentLight::radiance(Vec3 w, double &pdf) const {
  pdf = 0;
  if (!target_) return {};
  const Point2 sq = spherePoint(toLocal(w));
  const GridTarget::Cell c = target_->locate(sq);
  pdf = target_->cellDensity(c.i, c.j) * kInvFourPi;
  return texel(c);
}

double EnvironmentLight::pdf(Vec3 w) const {
  double p;
  radiance(w, p);
  return p;
}

std::optional<LightSample> EnvironmentLight::sampleCell(Point2 x, GridTarget::Cell c) const {
  const double p = target_->cellDensity(c.i, c.j) * kInvFourPi;
  if (!(p > 0)) return std::nullopt;  // a point off the target's support
  return LightSample{toWorld(sphereDirection(x)), texel(c), p};
}

std::optional<LightSample> EnvironmentLight::sampleTarget(Point2 x) const {
  if (!target_ || !(x.x >= 0 && x.x <= 1 && x.y >= 0 && x.y <= 1)) return std::nullopt;
  return sampleCell(x, target_->locate(x));
}

std::optional<LightSample> EnvironmentLight::sample(Point2 u) const {
  if (!target_) return std::nullopt;
  GridTarget::Cell c;
  const Point2 x = target_->invert(u, c).x;
  return sampleCell(x, c);
}

}  // namespace nuld
