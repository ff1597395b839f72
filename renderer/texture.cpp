#include "renderer/texture.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nuld {

Texture::Texture(const Image &image, Encoding encoding, Wrap wrapU, Wrap wrapV)
    : width_(image.width), height_(image.height), wrapU_(wrapU), wrapV_(wrapV) {
  if (width_ <= 0 || height_ <= 0 || image.channels <= 0 ||
      image.pixels.size() != std::size_t(width_) * height_ * image.channels)
    throw std::invalid_argument("texture: the image has no pixels");
  rgb_.resize(std::size_t(width_) * height_ * 3);
  // Grey and grey-alpha images spread their first channel.
  const bool grey = image.channels < 3;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      for (int c = 0; c < 3; ++c) {
        double v = image.at(x, y, grey ? 0 : c);
        if (!std::isfinite(v)) v = 0;
        if (encoding == Encoding::Srgb) v = srgbToLinear(std::clamp(v, 0.0, 1.0));
        rgb_[(std::size_t(y) * width_ + x) * 3 + c] = float(v);
      }
}

Rgb Texture::texel(int x, int y) const {
  const float *t = &rgb_[(std::size_t(y) * width_ + x) * 3];
  return {t[0], t[1], t[2]};
}

namespace {

// Texel index i of a row or column of n under `wrap`.
int wrapIndex(long long i, int n, Texture::Wrap wrap) {
  switch (wrap) {
    case Texture::Wrap::Clamp: return int(std::clamp<long long>(i, 0, n - 1));
    case Texture::Wrap::Mirror: {
      const long long period = 2LL * n;
      long long m = i % period;
      if (m < 0) m += period;
      return int(m < n ? m : period - 1 - m);
    }
    case Texture::Wrap::Repeat:
    default: {
      long long m = i % n;
      return int(m < 0 ? m + n : m);
    }
  }
}

}  // namespace

Rgb Texture::lookup(Point2 uv) const {
  // Far-away coordinates keep only their fraction's worth of precision;
  // those beyond 2^40 (or not finite) are taken as 0.
  const auto tame = [](double v) { return std::isfinite(v) && std::abs(v) < 0x1p40 ? v : 0.0; };
  const double x = tame(uv.x) * width_ - 0.5, y = tame(uv.y) * height_ - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const double tx = x - fx, ty = y - fy;
  const auto i0 = static_cast<long long>(fx), j0 = static_cast<long long>(fy);
  const int xa = wrapIndex(i0, width_, wrapU_), xb = wrapIndex(i0 + 1, width_, wrapU_);
  const int ya = wrapIndex(j0, height_, wrapV_), yb = wrapIndex(j0 + 1, height_, wrapV_);
  return (1 - ty) * ((1 - tx) * texel(xa, ya) + tx * texel(xb, ya)) +
         ty * ((1 - tx) * texel(xa, yb) + tx * texel(xb, yb));
}

void Texture::hashContent(ContentHash &h) const {
  h.add("texture").add(std::uint64_t(width_)).add(std::uint64_t(height_));
  h.add(std::uint64_t(wrapU_)).add(std::uint64_t(wrapV_));
  for (const float v : rgb_) h.add(double(v));
}

}  // namespace nuld
