#pragma once
// The comparison page of a render study (docs/studies.md, "The comparison
// page"): OUT/compare.html, which shows each scene's reference and every
// row's render at full size, to flip between by keys or clicks under one
// zoom, pan and exposure, with each render's error and HDR-FLIP maps one key
// away. It opens from the study folder in a browser with no server and
// fetches nothing from the network: the viewer (tools/study/compare/) is
// copied beside it, and each image is a script under OUT/compare/data/ (the
// render as RGBE bytes, its maps as PNG data), loaded when first shown.

#include <filesystem>
#include <string>

#include "sampler/io/image_io.h"

namespace nuld::study {

// Writes the page and its data from OUT/render.csv and the images the rows
// name; an image's data file is made again only when it is older than the
// image. `viewerDir` holds compare.html, viewer.js and viewer.css. Returns
// the page, or an empty path when the table has no rows. Throws
// std::runtime_error naming a file that cannot be read or written.
std::filesystem::path writeComparisonPage(const std::filesystem::path &out,
                                          const std::filesystem::path &viewerDir);

// An image's RGB as the page's RGBE bytes (Ward's shared exponent: channel
// c = (byte + 0.5) 2^(e - 136), e = 0 black), four per pixel: within 0.4 %
// of the pixel's largest channel. Negative and NaN values are 0, infinite
// ones the largest RGBE value.
std::string encodeRgbe(const Image &img);

}  // namespace nuld::study
