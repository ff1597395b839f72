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

Rgb EnvironmentLight::texel(Point2 sq) const {
  // Column from u; row from theta, matching the target's cells exactly.
  const int x = std::clamp(int(sq.x * image_.width), 0, image_.width - 1);
  const double theta = std::acos(std::clamp(1 - 2 * sq.y, -1.0, 1.0));
  const int y = std::clamp(int(theta / std::numbers::pi * image_.height), 0, image_.height - 1);
  return {image_.at(x, y, 0), image_.at(x, y, 1), image_.at(x, y, 2)};
}

Rgb EnvironmentLight::radiance(Vec3 w) const { return texel(spherePoint(toLocal(w))); }

double EnvironmentLight::pdf(Vec3 w) const {
  if (!target_) return 0;
  return target_->pdf(spherePoint(toLocal(w))) * kInvFourPi;
}

std::optional<LightSample> EnvironmentLight::sampleTarget(Point2 x) const {
  if (!target_) return std::nullopt;
  const double p = target_->pdf(x) * kInvFourPi;
  if (!(p > 0)) return std::nullopt;  // a point off the target's support
  const Vec3 wi = toWorld(sphereDirection(x));
  return LightSample{wi, texel(x), p};
}

std::optional<LightSample> EnvironmentLight::sample(Point2 u) const {
  if (!target_) return std::nullopt;
  return sampleTarget(target_->invert(u).x);
}

}  // namespace nuld
