#pragma once
// Error of a render against a reference, the false-colour error map, and the
// tone mapping for PNG previews.
//
// mse    = mean over pixels and RGB channels of (I - R)^2
// relmse = mean over pixels and RGB channels of (I - R)^2 / (R^2 + 0.01)
// (the 0.01 keeps black reference pixels from dominating, as in the common
// relMSE definition used by denoising and sampling papers).
// screen = mean over pixels and RGB channels of (G * (I - R))^2, the error
//          image low-passed by a Gaussian G of kScreenErrorSigma pixels
//          before squaring: the error a viewer sees at a normal distance,
//          where blue-noise error (high frequencies) fades and clumped,
//          white-noise error stays (the perceptual-error literature's
//          measure, e.g. Heitz and Belcour 2019, Ahmed and Wonka 2020).

#include <string>
#include <vector>

#include "sampler/io/image_io.h"

namespace nuld {

// relmse's 0.01, which a reference's own relative variance shares.
inline constexpr double kRelMseEpsilon = 0.01;

// The Gaussian's standard deviation in pixels; truncated at 3 sigma and
// renormalized at the image's borders.
inline constexpr double kScreenErrorSigma = 1.0;

// The share of an image's pixels whose error `winsorized` clips: the
// brightest errors (fireflies) that can rule an MSE.
inline constexpr double kWinsorizedShare = 0.001;

struct ImageError {
  double mse = 0, relmse = 0, screen = 0;
  // MSE with the largest pixel errors winsorized: the k largest pixels'
  // squared errors (each summed over its channels), k = max(1,
  // floor(kWinsorizedShare x pixels)), count as the (k + 1)-th largest. A
  // robust statistic beside MSE: where the two rank samplers differently, a
  // few pixels rule the MSE. An image of k pixels or fewer keeps its MSE.
  double winsorized = 0;
  // The share of the squared error in those k largest pixels (0 when there
  // is no error, or k + 1 pixels or fewer): near 1, the MSE is a handful of
  // fireflies.
  double topShare = 0;
  std::size_t nonFinitePixels = 0;  // in the image under test (counted, then skipped)
};

// "" when every value of `image` is a finite number, else the first that is
// not: "pixel (x, y) channel c is not a finite number".
std::string nonFinitePixel(const Image &image);

// Throws std::invalid_argument when the sizes or the channel counts differ
// (naming both) or a pixel of the reference is not finite ("reference: "
// and nonFinitePixel's words). The image under test may hold non-finite
// pixels: they are counted (nonFinitePixels) and left out of the error
// (their difference counts as 0 in the low-passed one).
ImageError compareImages(const Image &image, const Image &reference);

// `values` (width x height, one channel) convolved with the truncated,
// border-renormalized Gaussian of `sigma` pixels, separably.
std::vector<double> gaussianBlur(const std::vector<double> &values, int width, int height,
                                 double sigma);

// The radially averaged power spectrum of the error's luminance (I - R):
// over the largest power-of-two square centred in the image (side n), the
// 2D DFT's |F(k)|^2 / n^2 averaged over the frequencies k of each integer
// radius r = 0 .. n / 2 (r / n cycles per pixel). By Parseval the mean over
// all k is the error's mean square, so white-noise error is flat at its
// variance and blue-noise error rises with r. Empty for an image with a
// side under 2. The shapes and channel counts checked as compareImages
// checks them.
std::vector<double> errorPowerSpectrum(const Image &image, const Image &reference);

// Per-pixel relative squared error, log-scaled over [1e-4, 1] and coloured
// from dark blue (small) through green and yellow to white (large); the
// sizes and channel counts checked as compareImages checks them.
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
// Its rule on the name alone (a command checks it as it parses the option).
void checkRenderName(const std::string &exrPath);

}  // namespace nuld
