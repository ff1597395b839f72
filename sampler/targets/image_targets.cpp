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
  const bool luminance =
      weight == PixelWeight::Luminance || weight == PixelWeight::LuminanceCompensated;
  return luminance ? rec709Luminance(r, g, b) : (r + g + b) / 3;
}

// A lat-long map's row edges in the equal-area v = (1 - cos theta) / 2.
std::vector<double> equalAreaRowEdges(int rows) {
  std::vector<double> yEdges(rows + 1);
  for (int j = 0; j <= rows; ++j) yEdges[j] = 0.5 * (1 - std::cos(std::numbers::pi * j / rows));
  yEdges.front() = 0.0;
  yEdges.back() = 1.0;
  return yEdges;
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

bool isCompensated(PixelWeight weight) {
  return weight == PixelWeight::LuminanceCompensated ||
         weight == PixelWeight::ChannelMeanCompensated;
}

PixelWeight uncompensated(PixelWeight weight) {
  switch (weight) {
    case PixelWeight::LuminanceCompensated: return PixelWeight::Luminance;
    case PixelWeight::ChannelMeanCompensated: return PixelWeight::ChannelMean;
    case PixelWeight::Luminance:
    case PixelWeight::ChannelMean: return weight;
  }
  return weight;
}

double pixelWeight(double r, double g, double b, PixelWeight weight) {
  return std::max(0.0, colourWeight(r, g, b, weight));
}

double envmapCompensation(const Image &latlong, PixelWeight weight) {
  if (!isCompensated(weight)) return 0;
  const int W = latlong.width, H = latlong.height;
  const std::vector<double> yEdges = equalAreaRowEdges(H);
  // The mean over the sphere: rows weighted by their share of the solid angle.
  double mean = 0, brightest = 0;
  for (int j = 0; j < H; ++j) {
    double row = 0;
    for (int i = 0; i < W; ++i) {
      const double w = std::max(0.0, rawWeight(latlong, i, j, weight));
      row += w;
      brightest = std::max(brightest, w);
    }
    mean += row * (yEdges[j + 1] - yEdges[j]) / W;
  }
  return brightest > mean ? mean : 0.0;
}

const char *envmapFamily(PixelWeight weight) {
  switch (weight) {
    case PixelWeight::Luminance: return "envmap";
    case PixelWeight::ChannelMean: return "envmap-mean";
    case PixelWeight::LuminanceCompensated: return "envmap-compensated";
    case PixelWeight::ChannelMeanCompensated: return "envmap-mean-compensated";
  }
  return "envmap";
}

std::unique_ptr<GridTarget> makeImageTarget(const Image &image, const std::string &source) {
  const std::vector<double> density = densities(image, PixelWeight::Luminance, true, source);
  return std::make_unique<GridTarget>(GridTarget::uniformEdges(image.width),
                                      GridTarget::uniformEdges(image.height), density,
                                      "image:" + source, Domain::Square, source);
}

std::unique_ptr<GridTarget> makeEnvmapTarget(const Image &latlong, const std::string &source,
                                             PixelWeight weight, double *compensation) {
  const int W = latlong.width, H = latlong.height;
  std::vector<double> density = densities(latlong, weight, false, source);
  const double offset = envmapCompensation(latlong, weight);
  if (offset > 0)
    for (double &d : density) d = std::max(0.0, d - offset);
  if (compensation) *compensation = offset;
  return std::make_unique<GridTarget>(GridTarget::uniformEdges(W), equalAreaRowEdges(H), density,
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
