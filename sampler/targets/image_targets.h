#pragma once
// Grid targets read from image files: an image on the unit square (density
// from luminance, the picture upright: image row 0 is the top, y = 1), and a
// lat-long environment map on the sphere (row 0 = zenith, luminance per solid
// angle, rows re-gridded to the equal-area v = (1 - cos theta) / 2).

#include <memory>
#include <string>

#include "sampler/io/image_io.h"
#include "sampler/targets/grid_target.h"

namespace nuld {

std::unique_ptr<GridTarget> makeImageTarget(const Image &image, const std::string &source);
std::unique_ptr<GridTarget> makeEnvmapTarget(const Image &latlong, const std::string &source);

std::unique_ptr<GridTarget> loadImageTarget(const std::string &path);
std::unique_ptr<GridTarget> loadEnvmapTarget(const std::string &path);

}  // namespace nuld
