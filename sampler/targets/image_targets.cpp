#include "sampler/targets/image_targets.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sampler/diagnostics.h"
#include "sampler/io/round_trip.h"

namespace nuld {
namespace {

// A pixel's weight as the image gives it: its one channel for a grey image
// (its density under either weight), else the weight of its colour.
double colourWeight(double r, double g, double b, PixelWeight weight) {
  return weight == PixelWeight::Luminance ? rec709Luminance(r, g, b) : (r + g + b) / 3;
}
double rawWeight(const Image &img, int x, int y, PixelWeight weight) {
  if (img.channels < 3) return img.at(x, y, 0);
  return colourWeight(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2), weight);
}

// The pixels' densities, row j of the result from image row j (or H - 1 - j
// when flipped). Negative weights (from colour conversions of HDR data)
// carry no probability: they become zero, and the user is told how many.
std::vector<double> densities(const Image &img, PixelWeight weight, bool flipRows,
                              const std::string &source) {
  const int W = img.width, H = img.height;
  std::vector<double> density(std::size_t(W) * H);
  std::size_t negative = 0;
  double lowest = 0;
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) {
      const double w = rawWeight(img, i, flipRows ? H - 1 - j : j, weight);
      negative += w < 0;
      lowest = std::min(lowest, w);
      density[std::size_t(j) * W + i] = std::max(0.0, w);
    }
  if (negative > 0)
    warning(source + ": " + std::to_string(negative) + " of " + std::to_string(density.size()) +
            " pixels have a negative weight (down to " + formatShort(lowest) +
            "); their density is 0");
  return density;
}

}  // namespace

double pixelWeight(double r, double g, double b, PixelWeight weight) {
  return std::max(0.0, colourWeight(r, g, b, weight));
}

const char *envmapFamily(PixelWeight weight) {
  return weight == PixelWeight::Luminance ? "envmap" : "envmap-mean";
}

std::unique_ptr<GridTarget> makeImageTarget(const Image &image, const std::string &source) {
  const std::vector<double> density = densities(image, PixelWeight::Luminance, true, source);
  return std::make_unique<GridTarget>(GridTarget::uniformEdges(image.width),
                                      GridTarget::uniformEdges(image.height), density,
                                      "image:" + source, Domain::Square, source);
}

std::unique_ptr<GridTarget> makeEnvmapTarget(const Image &latlong, const std::string &source,
                                             PixelWeight weight) {
  const int W = latlong.width, H = latlong.height;
  std::vector<double> yEdges(H + 1);
  for (int j = 0; j <= H; ++j) yEdges[j] = 0.5 * (1 - std::cos(std::numbers::pi * j / H));
  yEdges.front() = 0.0;
  yEdges.back() = 1.0;
  const std::vector<double> density = densities(latlong, weight, false, source);
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
