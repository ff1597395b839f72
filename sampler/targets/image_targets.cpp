#include "sampler/targets/image_targets.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace nuld {
namespace {

// Negative values (from colour conversions of HDR data) carry no
// probability; they are clamped to zero rather than rejected. A grey image's
// one channel is its density under either weight.
double densityOf(const Image &img, int x, int y, PixelWeight weight) {
  if (img.channels < 3) return std::max(0.0, double(img.at(x, y, 0)));
  return pixelWeight(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2), weight);
}

}  // namespace

double pixelWeight(double r, double g, double b, PixelWeight weight) {
  const double w = weight == PixelWeight::Luminance ? rec709Luminance(r, g, b) : (r + g + b) / 3;
  return std::max(0.0, w);
}

const char *envmapFamily(PixelWeight weight) {
  return weight == PixelWeight::Luminance ? "envmap" : "envmap-mean";
}

std::unique_ptr<GridTarget> makeImageTarget(const Image &image, const std::string &source) {
  const int W = image.width, H = image.height;
  std::vector<double> density(std::size_t(W) * H);
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i)
      density[std::size_t(j) * W + i] = densityOf(image, i, H - 1 - j, PixelWeight::Luminance);
  return std::make_unique<GridTarget>(GridTarget::uniformEdges(W), GridTarget::uniformEdges(H),
                                      density, "image:" + source, Domain::Square, source);
}

std::unique_ptr<GridTarget> makeEnvmapTarget(const Image &latlong, const std::string &source,
                                             PixelWeight weight) {
  const int W = latlong.width, H = latlong.height;
  std::vector<double> yEdges(H + 1);
  for (int j = 0; j <= H; ++j) yEdges[j] = 0.5 * (1 - std::cos(std::numbers::pi * j / H));
  yEdges.front() = 0.0;
  yEdges.back() = 1.0;
  std::vector<double> density(std::size_t(W) * H);
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) density[std::size_t(j) * W + i] = densityOf(latlong, i, j, weight);
  return std::make_unique<GridTarget>(GridTarget::uniformEdges(W), std::move(yEdges), density,
                                      std::string(envmapFamily(weight)) + ":" + source,
                                      Domain::Sphere, source);
}

std::unique_ptr<GridTarget> loadImageTarget(const std::string &path) {
  return makeImageTarget(readImage(path), path);
}

std::unique_ptr<GridTarget> loadEnvmapTarget(const std::string &path, PixelWeight weight) {
  return makeEnvmapTarget(readImage(path), path, weight);
}

}  // namespace nuld
