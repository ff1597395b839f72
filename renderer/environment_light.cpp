#include "renderer/environment_light.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "materials/sphere_map.h"
#include "sampler/diagnostics.h"
#include "sampler/io/round_trip.h"
#include "sampler/targets/image_targets.h"

namespace nuld {
namespace {

// Keeps three channels (grey maps are replicated), clamps negative values
// (colour conversions of HDR data produce them; the user is told how many)
// and applies the scale.
Image toRgb(const Image &in, double scale, const std::string &source) {
  if (in.width <= 0 || in.height <= 0 || in.channels <= 0)
    throw std::invalid_argument(source + ": empty environment map");
  if (!(scale >= 0) || !std::isfinite(scale))
    throw std::invalid_argument(source + ": environment scale must be finite and >= 0");
  Image out{in.width, in.height, 3, std::vector<float>(std::size_t(in.width) * in.height * 3)};
  std::size_t negative = 0;
  float lowest = 0;
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = in.at(x, y, in.channels >= 3 ? c : 0);
        if (!std::isfinite(v))
          throw std::invalid_argument(source + ": pixel (" + std::to_string(x) + ", " +
                                      std::to_string(y) + ") is not finite");
        negative += v < 0;
        lowest = std::min(lowest, v);
        out.at(x, y, c) = float(std::max(0.0f, v) * scale);
      }
  if (negative > 0)
    warning(source + ": " + std::to_string(negative) + " of " + std::to_string(out.pixels.size()) +
            " pixel values are negative (down to " + formatShort(lowest) +
            "); the environment light treats them as 0");
  return out;
}

// The shortest rotation taking +Y to `up` (unit), applied to v (Rodrigues'
// formula about the axis Y x up); for up = -Y, where that axis vanishes, the
// half-turn about +X.
Vec3 tiltUp(Vec3 v, Vec3 up) {
  const Vec3 axis = cross(Vec3{0, 1, 0}, up);
  const double c = up.y, s = length(axis);  // cos and sin of the tilt
  if (s == 0) return c > 0 ? v : Vec3{v.x, -v.y, -v.z};
  const Vec3 a = axis / s;
  return c * v + s * cross(a, v) + (1 - c) * dot(a, v) * a;
}

}  // namespace

EnvironmentLight::EnvironmentLight(Image latlong, double scale, double rotationDegrees,
                                   std::string source, Vec3 up, PixelWeight weight)
    : weight_(weight), source_(std::move(source)) {
  if (!isFinite(up) || !(length(up) > 0))
    throw std::invalid_argument(source_ +
                                ": the environment's up direction must be a finite, "
                                "non-zero vector");
  up = normalize(up);
  const Image image = toRgb(latlong, scale, source_);
  // The twin from the scaled, clamped map at scale 1: the same texels, and
  // the warnings about the map are said once.
  if (isCompensated(weight))
    uncompensated_ = std::make_shared<const EnvironmentLight>(image, 1.0, rotationDegrees, source_,
                                                              up, nuld::uncompensated(weight));
  width_ = image.width;
  height_ = image.height;
  const double rot = rotationDegrees * std::numbers::pi / 180;
  cosRot_ = std::cos(rot);
  sinRot_ = std::sin(rot);
  tilted_ = up.x != 0 || up.z != 0 || !(up.y > 0);
  const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int k = 0; k < 3; ++k) tilt_[k] = tiltUp(axes[k], up);
  bool black = true;
  for (float v : image.pixels) black = black && v == 0;
  // A black map emits nothing and has nothing to sample: no target.
  if (black) return;
  target_ = makeEnvmapTarget(image, source_, weight_, &compensation_);
  reserveLargeTable(texels_, std::size_t(width_) * height_);
  texels_.resize(std::size_t(width_) * height_);
  // The target's density is the weight (clamped at 0, which the radiance
  // already is) normalized: its ratio to the weight is the same in every
  // cell, read here from the brightest one.
  double brightest = 0;
  for (int j = 0; j < height_; ++j)
    for (int i = 0; i < width_; ++i) {
      Texel &t = texels_[std::size_t(j) * width_ + i];
      t = {{image.at(i, j, 0), image.at(i, j, 1), image.at(i, j, 2)}};
      const double w = pixelWeight(t.rgb[0], t.rgb[1], t.rgb[2], weight_) - compensation_;
      if (w > brightest) {
        brightest = w;
        pdfPerWeight_ = target_->cellDensity(i, j) * kInvFourPi / w;
      }
    }
}

void EnvironmentLight::hashContent(ContentHash &h) const {
  h.add(std::uint64_t(width_)).add(std::uint64_t(height_));
  h.add(std::string_view(reinterpret_cast<const char *>(texels_.data()),
                         texels_.size() * sizeof(Texel)));
  h.add(toString(weight_)).add(compensation_).add(cosRot_).add(sinRot_);
  for (const Vec3 &axis : tilt_) h.add(axis.x).add(axis.y).add(axis.z);
}

// Map frame -> world at up = +Y: z up, phi = 0 towards -Z, phi = pi/2
// towards +X; turned about +Y by the rotation; then, only when `up` is not
// +Y, tilted (the common case skips the matrix: these run for every light
// sample and escaping ray).
Vec3 EnvironmentLight::toWorld(Vec3 l) const {
  const Vec3 w{l.y, l.z, -l.x};
  const Vec3 r{cosRot_ * w.x + sinRot_ * w.z, w.y, -sinRot_ * w.x + cosRot_ * w.z};
  return tilted_ ? r.x * tilt_[0] + r.y * tilt_[1] + r.z * tilt_[2] : r;
}

Vec3 EnvironmentLight::toLocal(Vec3 w) const {
  if (tilted_) w = {dot(w, tilt_[0]), dot(w, tilt_[1]), dot(w, tilt_[2])};
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

Rgb EnvironmentLight::radiance(Vec3 w, double &pdf) const { return radiance(find(w), pdf); }

EnvironmentLight::Lookup EnvironmentLight::find(Vec3 w) const {
  if (!target_) return {};
  const Texel &t = texel(target_->locate(spherePoint(toLocal(w))));
  __builtin_prefetch(&t.rgb[0]);
  __builtin_prefetch(&t.rgb[2]);  // a texel may straddle two cache lines
  return {&t};
}

Rgb EnvironmentLight::radiance(Lookup lookup, double &pdf) const {
  pdf = 0;
  if (!lookup.texel) return {};
  const Texel &t = *static_cast<const Texel *>(lookup.texel);
  const Rgb L = rgbOf(t);
  pdf = pdfOf(L);
  return L;
}

double EnvironmentLight::pdf(Vec3 w) const {
  double p;
  radiance(w, p);
  return p;
}

std::optional<LightSample> EnvironmentLight::sampleCell(Point2 x, GridTarget::Cell c) const {
  const Rgb L = rgbOf(texel(c));
  const double pdf = pdfOf(L);
  if (!(pdf > 0)) return std::nullopt;  // a point off the target's support
  return LightSample{toWorld(sphereDirection(x)), L, pdf};
}

std::optional<LightSample> EnvironmentLight::sampleTarget(Point2 x) const {
  if (!target_ || !(x.x >= 0 && x.x <= 1 && x.y >= 0 && x.y <= 1)) return std::nullopt;
  return sampleCell(x, target_->locate(x));
}

std::optional<LightSample> EnvironmentLight::sample(Point2 u) const {
  if (!target_) return std::nullopt;
  const GridTarget::Draw d = target_->draw(u);
  return sampleCell(d.x, d.cell);
}

namespace {
constexpr std::size_t kGroup = 16;  // points per pass of the batch forms
}  // namespace

void EnvironmentLight::sample(std::span<const Point2> u,
                              std::span<std::optional<LightSample>> out) const {
  if (!target_) return std::fill(out.begin(), out.end(), std::nullopt);
  for (std::size_t first = 0; first < u.size(); first += kGroup) {
    const std::size_t n = std::min(kGroup, u.size() - first);
    Point2 x[kGroup];
    GridTarget::Cell cell[kGroup];
    target_->invert(u.subspan(first, n), std::span(x, n), std::span(cell, n));
    for (std::size_t k = 0; k < n; ++k) __builtin_prefetch(&texel(cell[k]));
    for (std::size_t k = 0; k < n; ++k) out[first + k] = sampleCell(x[k], cell[k]);
  }
}

void EnvironmentLight::sampleTarget(std::span<const Point2> x,
                                    std::span<std::optional<LightSample>> out) const {
  for (std::size_t first = 0; first < x.size(); first += kGroup) {
    const std::size_t n = std::min(kGroup, x.size() - first);
    bool inside[kGroup];
    GridTarget::Cell cell[kGroup];
    for (std::size_t k = 0; k < n; ++k) {
      const Point2 p = x[first + k];
      inside[k] = target_ && inUnitSquare(p);
      if (inside[k]) __builtin_prefetch(&texel(cell[k] = target_->locate(p)));
    }
    for (std::size_t k = 0; k < n; ++k)
      out[first + k] = inside[k] ? sampleCell(x[first + k], cell[k]) : std::nullopt;
  }
}

double EnvironmentLight::meanLuminance() const {
  // Row j of the lat-long map spans polar angles pi j / H to pi (j + 1) / H:
  // its share of the sphere is half the difference of their cosines.
  double mean = 0;
  for (int j = 0; j < height_ && !texels_.empty(); ++j) {
    const double share = 0.5 * (std::cos(std::numbers::pi * j / height_) -
                                std::cos(std::numbers::pi * (j + 1) / height_));
    double row = 0;
    for (int i = 0; i < width_; ++i) row += rgbOf(texels_[std::size_t(j) * width_ + i]).luminance();
    mean += share * row / width_;
  }
  return mean;
}

}  // namespace nuld
