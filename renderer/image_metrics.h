#pragma once
// Error of a render against a reference, the false-colour error map, and the
// tone mapping for PNG previews.
//
// mse    = mean over pixels and RGB channels of (I - R)^2
// relmse = mean over pixels and RGB channels of (I - R)^2 / (R^2 + 0.01)
// (the 0.01 keeps black reference pixels from dominating, as in the common
// relMSE definition used by denoising and sampling papers).

#include <string>

#include "sampler/io/image_io.h"

namespace nuld {

struct ImageError {
  double mse = 0, relmse = 0;
  std::size_t nonFinitePixels = 0;  // in the image under test (counted, then skipped)
};

// Throws std::invalid_argument when the sizes differ (naming both sizes).
ImageError compareImages(const Image &image, const Image &reference);

// Per-pixel relative squared error, log-scaled over [1e-4, 1] and coloured
// from dark blue (small) through green and yellow to white (large).
Image errorMap(const Image &image, const Image &reference);

// Exposure, clamp and the sRGB transfer curve: an 8-bit-ready preview.
Image toneMap(const Image &linear, double exposure = 1.0);

// Writes image.exr plus a tone-mapped image.png beside it (both atomic),
// both carrying `attributes` (renderAttributes in render.h).
void writeRender(const std::string &exrPath, const Image &image,
                 const ImageAttributes &attributes = {});
// The checks writeRender makes of its two outputs, for a command to make
// before it spends time rendering.
void checkRenderOutputs(const std::string &exrPath);

}  // namespace nuld
