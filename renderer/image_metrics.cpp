#include "renderer/image_metrics.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <complex>
#include <filesystem>
#include <functional>
#include <numbers>
#include <stdexcept>

#include "sampler/io/atomic_file.h"

namespace nuld {
namespace {

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
double relativeSquared(double d, double r) { return d * d / (r * r + kRelMseEpsilon); }

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
  std::vector<double> pixelError;  // per finite pixel, summed over the channels
  pixelError.reserve(std::size_t(img.width) * img.height);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      bool finite = true;
      for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(channel(img, x, y, c));
      if (!finite) {
        ++err.nonFinitePixels;
        continue;
      }
      double pixel = 0;
      for (int c = 0; c < 3; ++c) {
        const double r = channel(ref, x, y, c), d = channel(img, x, y, c) - r;
        pixel += d * d;
        rel += relativeSquared(d, r);
        diff[c][std::size_t(y) * img.width + x] = d;
      }
      se += pixel;
      pixelError.push_back(pixel);
      count += 3;
    }
  err.mse = count ? se / count : 0;
  err.relmse = count ? rel / count : 0;
  const std::size_t k =
      std::max<std::size_t>(1, std::size_t(kWinsorizedShare * double(pixelError.size())));
  err.winsorized = err.mse;
  if (pixelError.size() > k) {
    // The k largest first, then the (k + 1)-th largest at index k: the clip.
    std::nth_element(pixelError.begin(), pixelError.begin() + std::ptrdiff_t(k), pixelError.end(),
                     std::greater<>());
    // The rest summed on its own, not as se - top: a firefly of 1e6 would
    // leave rounding of its size in the difference.
    const double clip = pixelError[k];
    double top = 0, rest = 0;
    for (std::size_t i = 0; i < k; ++i) top += pixelError[i];
    for (std::size_t i = k; i < pixelError.size(); ++i) rest += pixelError[i];
    err.winsorized = (rest + double(k) * clip) / double(count);
    err.topShare = se > 0 ? top / se : 0;
  }
  double screen = 0;
  for (const auto &d : diff)
    for (const double v : gaussianBlur(d, img.width, img.height, kScreenErrorSigma))
      screen += v * v;
  err.screen = screen / (3.0 * img.width * img.height);
  return err;
}

namespace {

// In-place radix-2 FFT of `a` (its size a power of two), every `stride`th
// value from `first`.
void fft(std::vector<std::complex<double>> &a, std::size_t first, std::size_t n,
         std::size_t stride) {
  const auto at = [&](std::size_t i) -> std::complex<double> & { return a[first + i * stride]; };
  for (std::size_t i = 1, j = 0; i < n; ++i) {  // bit-reversed order
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(at(i), at(j));
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const double angle = -2 * std::numbers::pi / double(len);
    for (std::size_t i = 0; i < n; i += len)
      for (std::size_t k = 0; k < len / 2; ++k) {
        const std::complex<double> w = std::polar(1.0, angle * double(k));
        const std::complex<double> u = at(i + k), v = at(i + k + len / 2) * w;
        at(i + k) = u + v;
        at(i + k + len / 2) = u - v;
      }
  }
}

}  // namespace

std::vector<double> errorPowerSpectrum(const Image &img, const Image &ref) {
  requireSameShape(img, ref);
  const int side = std::min(img.width, img.height);
  if (side < 2) return {};
  const std::size_t n = std::bit_floor(std::size_t(side));
  const int x0 = (img.width - int(n)) / 2, y0 = (img.height - int(n)) / 2;
  std::vector<std::complex<double>> f(n * n);
  for (std::size_t y = 0; y < n; ++y)
    for (std::size_t x = 0; x < n; ++x) {
      const int px = x0 + int(x), py = y0 + int(y);
      const double e = rec709Luminance(channel(img, px, py, 0), channel(img, px, py, 1),
                                       channel(img, px, py, 2)) -
                       rec709Luminance(channel(ref, px, py, 0), channel(ref, px, py, 1),
                                       channel(ref, px, py, 2));
      f[y * n + x] = std::isfinite(e) ? e : 0.0;  // a non-finite pixel counts as no error
    }
  for (std::size_t y = 0; y < n; ++y) fft(f, y * n, n, 1);
  for (std::size_t x = 0; x < n; ++x) fft(f, x, n, n);
  std::vector<double> sum(n / 2 + 1, 0.0), count(n / 2 + 1, 0.0);
  for (std::size_t y = 0; y < n; ++y)
    for (std::size_t x = 0; x < n; ++x) {
      // Signed frequencies, so that the radius is the distance from 0.
      const double fx = x <= n / 2 ? double(x) : double(x) - double(n),
                   fy = y <= n / 2 ? double(y) : double(y) - double(n);
      const auto r = std::size_t(std::lround(std::hypot(fx, fy)));
      if (r > n / 2) continue;  // the corners beyond the inscribed circle
      sum[r] += std::norm(f[y * n + x]) / double(n * n);
      count[r] += 1;
    }
  for (std::size_t r = 0; r < sum.size(); ++r) sum[r] /= count[r];
  return sum;
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
    v = float(linearToSrgb(x));
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
  writeImagePair(exrPath, image, std::filesystem::path(exrPath).replace_extension(".png").string(),
                 toneMap(image), attributes);
}

}  // namespace nuld
