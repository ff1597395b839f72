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

void requireSameShape(const Image &a, const Image &b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("images differ in size: " + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " vs reference " +
                                std::to_string(b.width) + "x" + std::to_string(b.height));
  // A grey image against a colour one (or RGB against RGBA) compares
  // different things channel by channel.
  if (a.channels != b.channels)
    throw std::invalid_argument("images differ in channels: " + std::to_string(a.channels) +
                                " vs reference " + std::to_string(b.channels));
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

std::string nonFinitePixel(const Image &img) {
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < img.channels; ++c)
        if (!std::isfinite(img.at(x, y, c)))
          return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                 std::to_string(c) + " is not a finite number";
  return "";
}

std::vector<double> gaussianBlur(const std::vector<double> &values, int width, int height,
                                 double sigma) {
  const int radius = std::max(1, int(std::ceil(3 * sigma)));
  std::vector<double> kernel(2 * radius + 1);
  for (int k = -radius; k <= radius; ++k)
    kernel[k + radius] = std::exp(-0.5 * (k * k) / (sigma * sigma));
  // One pass along a line of `n` values `stride` apart; the weights that
  // fall outside the image are left out and the rest renormalized.
  const auto pass = [&](const std::vector<double> &in, int n, int lines, std::size_t stride,
                        std::size_t lineStride) {
    std::vector<double> out(in.size());
    for (int line = 0; line < lines; ++line)
      for (int i = 0; i < n; ++i) {
        double sum = 0, weight = 0;
        for (int k = std::max(-radius, -i); k <= std::min(radius, n - 1 - i); ++k) {
          const double w = kernel[k + radius];
          sum += w * in[line * lineStride + std::size_t(i + k) * stride];
          weight += w;
        }
        out[line * lineStride + std::size_t(i) * stride] = sum / weight;
      }
    return out;
  };
  return pass(pass(values, width, height, 1, std::size_t(width)), height, width, std::size_t(width),
              1);
}

ImageError compareImages(const Image &img, const Image &ref) {
  requireSameShape(img, ref);
  if (const std::string why = nonFinitePixel(ref); !why.empty())
    throw std::invalid_argument("reference: " + why);
  ImageError err;
  double se = 0, rel = 0;
  std::size_t count = 0;
  // Each channel's difference image, for the low-passed error.
  std::array<std::vector<double>, 3> diff;
  for (auto &d : diff) d.assign(std::size_t(img.width) * img.height, 0.0);
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
        diff[c][std::size_t(y) * img.width + x] = d;
      }
      count += 3;
    }
  err.mse = count ? se / count : 0;
  err.relmse = count ? rel / count : 0;
  double screen = 0;
  for (const auto &d : diff)
    for (const double v : gaussianBlur(d, img.width, img.height, kScreenErrorSigma))
      screen += v * v;
  err.screen = screen / (3.0 * img.width * img.height);
  return err;
}

Image errorMap(const Image &img, const Image &ref) {
  requireSameShape(img, ref);
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

void checkRenderName(const std::string &exrPath) {
  if (std::filesystem::path(exrPath).extension() != ".exr")
    throw std::invalid_argument(exrPath +
                                ": a render is written as a linear .exr with a tone-mapped .png "
                                "beside it; name an .exr file");
}

void checkRenderOutputs(const std::string &exrPath) {
  // What every command says of a device, pipe or directory first (the one
  // rule for outputs, docs/usage.md), then the render's own rule: any other
  // name would lose the linear image (a PNG holds 8 bits) and then be
  // overwritten by the tone-mapped one.
  checkDestination(exrPath);
  checkRenderName(exrPath);
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
