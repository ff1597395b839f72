#pragma once
// Grid targets read from image files: an image on the unit square (density
// from luminance, the picture upright: image row 0 is the top, y = 1), and a
// lat-long environment map on the sphere (row 0 = zenith, density per solid
// angle, rows re-gridded to the equal-area v = (1 - cos theta) / 2).
//
// A map's density is its luminance (`envmap:FILE`, the supplement's) or the
// mean of its channels (`envmap-mean:FILE`, as pbrt-v4 and Cycles weight
// environment maps): luminance all but ignores blue light (weight 0.07), so
// a map lit by blue windows is undersampled where its blue channel is
// bright, and a render's blue channel pays for it in variance
// (tools/experiments/README.md, "Cross-check against Cycles").

#include <memory>
#include <string>

#include "sampler/io/image_io.h"
#include "sampler/targets/grid_target.h"

namespace nuld {

// How a pixel's colour becomes density (negative values count as 0).
enum class PixelWeight { Luminance, ChannelMean };
double pixelWeight(double r, double g, double b, PixelWeight weight);
// The spec family of an environment map weighted so: envmap or envmap-mean.
const char *envmapFamily(PixelWeight weight);

std::unique_ptr<GridTarget> makeImageTarget(const Image &image, const std::string &source);
std::unique_ptr<GridTarget> makeEnvmapTarget(const Image &latlong, const std::string &source,
                                             PixelWeight weight = PixelWeight::Luminance);

std::unique_ptr<GridTarget> loadImageTarget(const std::string &path);
std::unique_ptr<GridTarget> loadEnvmapTarget(const std::string &path,
                                             PixelWeight weight = PixelWeight::Luminance);

}  // namespace nuld
