#include "renderer/image_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "sampler/io/atomic_file.h"

namespace nuld {
namespace {

constexpr double kRelEpsilon = 0.01;

void requireSameSize(const Image &a, const Image &b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("images differ in size: " + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " vs reference " +
                                std::to_string(b.width) + "x" + std::to_string(b.height));
}

// The squared error d^2 of one channel relative to its reference value r.
double relativeSquared(double d, double r) { return d * d / (r * r + kRelEpsilon); }

double channel(const Image &img, int x, int y, int c) {
  return img.at(x, y, img.channels >= 3 ? c : 0);
}

double pixelRelError(const Image &img, const Image &ref, int x, int y) {
  double e = 0;
  for (int c = 0; c < 3; ++c) {
    const double r = channel(ref, x, y, c), d = channel(img, x, y, c) - r;
    e += relativeSquared(d, r);
  }
  return e / 3;
}

}  // namespace

ImageError compareImages(const Image &img, const Image &ref) {
  requireSameSize(img, ref);
  ImageError err;
  double se = 0, rel = 0;
  std::size_t count = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      bool finite = true;
      for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(channel(img, x, y, c));
      if (!finite) {
        ++err.nonFinitePixels;
        continue;
      }
      for (int c = 0; c < 3; ++c) {
        const double r = channel(ref, x, y, c), d = channel(img, x, y, c) - r;
        se += d * d;
        rel += relativeSquared(d, r);
      }
      count += 3;
    }
  err.mse = count ? se / count : 0;
  err.relmse = count ? rel / count : 0;
  return err;
}

Image errorMap(const Image &img, const Image &ref) {
  requireSameSize(img, ref);
  // Piecewise-linear ramp: dark blue, blue, green, yellow, white.
  static constexpr std::array<std::array<double, 3>, 5> ramp{
      {{0.02, 0.02, 0.15}, {0.1, 0.3, 0.9}, {0.1, 0.8, 0.3}, {1.0, 0.9, 0.1}, {1, 1, 1}}};
  Image out{img.width, img.height, 3, std::vector<float>(std::size_t(img.width) * img.height * 3)};
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double e = pixelRelError(img, ref, x, y);
      const double t =
          std::isfinite(e) ? std::clamp((std::log10(std::max(e, 1e-12)) + 4) / 4, 0.0, 1.0) : 1.0;
      const double f = t * (ramp.size() - 1);
      const int i = std::min(int(f), int(ramp.size()) - 2);
      for (int c = 0; c < 3; ++c)
        out.at(x, y, c) = float(ramp[i][c] + (f - i) * (ramp[i + 1][c] - ramp[i][c]));
    }
  return out;
}

Image toneMap(const Image &linear, double exposure) {
  Image out = linear;
  for (float &v : out.pixels) {
    const double x = std::isfinite(v) ? std::clamp(double(v) * exposure, 0.0, 1.0) : 0.0;
    v = float(x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055);
  }
  return out;
}

void checkRenderOutputs(const std::string &exrPath) {
  // What every command says of a device, pipe or directory first (the one
  // rule for outputs, docs/usage.md), then the render's own rule: any other
  // name would lose the linear image (a PNG holds 8 bits) and then be
  // overwritten by the tone-mapped one.
  checkDestination(exrPath);
  if (std::filesystem::path(exrPath).extension() != ".exr")
    throw std::invalid_argument(exrPath +
                                ": a render is written as a linear .exr with a tone-mapped .png "
                                "beside it; name an .exr file");
  checkDestination(std::filesystem::path(exrPath).replace_extension(".png"));
}

void writeRender(const std::string &exrPath, const Image &image,
                 const ImageAttributes &attributes) {
  checkRenderOutputs(exrPath);
  writeImage(exrPath, image, attributes);
  writeImage(std::filesystem::path(exrPath).replace_extension(".png").string(), toneMap(image),
             attributes);
}

}  // namespace nuld
