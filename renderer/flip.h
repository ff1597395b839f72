#pragma once
// FLIP (written with a mirrored F), NVIDIA's perceptual difference of two
// images seen alternately ("flipped") on a monitor: a per-pixel error in
// [0, 1] and its mean.
//
//   LDR-FLIP: Andersson, Nilsson, Akenine-Moller, Oskarsson, Astrom and
//     Fairchild, "FLIP: A Difference Evaluator for Alternating Images",
//     HPG 2020.
//   HDR-FLIP: Andersson, Nilsson, Shirley and Akenine-Moller, "Visualizing
//     Errors in Rendered High Dynamic Range Images", Eurographics 2021
//     short paper.
//
// Our own implementation of the papers. Where a paper leaves a constant or
// a detail open, we followed NVIDIA's reference code, github.com/NVlabs/flip
// v1.6 (src/cpp/FLIP.h, with src/pytorch/flip_loss.py as a second reading):
//   * sRGB transfer curve (IEC 61966-2-1) and the linear sRGB -> XYZ matrix
//     in its exact rational form; the reference white is that matrix's image
//     of RGB (1, 1, 1) (D65), and XYZ -> RGB is its inverse, computed here;
//   * the CSF Gaussians (a1, b1, a2, b2): achromatic (1, 0.0047, 0, -),
//     red-green (1, 0.0053, 0, -), blue-yellow (34.1, 0.04, 13.5, 0.025),
//     the kernel radius ceil(3 sqrt(0.04 / (2 pi^2)) ppd), both images'
//     borders clamped to the edge;
//   * qc = 0.7, pc = 0.4, pt = 0.95, w = 0.082 degrees, qf = 0.5, and cmax
//     as the Hunt-adjusted HyAB distance of linear green to linear blue;
//   * the feature kernels' radius ceil(3 sigma), sigma = w ppd / 2, with
//     the positive and the negative weights each normalised to +-1;
//   * HDR: the ACES fit (Narkowicz 2016) with the 0.6 pre-exposure folded
//     into its coefficients, t = 0.85 for both exposure ends, the median
//     taken as element n/2 of the sorted luminances, and
//     count = max(2, ceil(stop - start)).
// The separable filters compute exactly the paper's 2D kernels (a product of
// 1D Gaussians per term of the blue-yellow sum), as the reference does.

#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "sampler/io/image_io.h"

namespace nuld {

// The viewer: a monitor `monitorWidthMeters` wide showing
// `monitorWidthPixels` pixels across, seen from `monitorDistanceMeters`.
struct FlipViewing {
  double monitorDistanceMeters = 0.7, monitorWidthMeters = 0.7, monitorWidthPixels = 3840;
  // Pixels per degree of visual angle, in FLIP's small-angle form
  // d (n / w) pi / 180 (about 67.02 at the defaults).
  double pixelsPerDegree() const;
};

struct FlipResult {
  std::vector<float> map;  // width x height, row 0 at the top, values in [0, 1]
  int width = 0, height = 0;
  double mean = 0;  // arithmetic mean of the map
};

// LDR-FLIP of two sRGB-encoded display images (values clamped to [0, 1]).
// Needs 3 or more channels (a 4th, alpha, is ignored) and equal sizes; throws
// std::invalid_argument naming what is wrong (sizes, channels, the first
// non-finite pixel, a non-positive viewing value). Symmetric in its images.
FlipResult ldrFlip(const Image &test, const Image &reference, const FlipViewing &v = {});

// HDR-FLIP's exposures, each given one overriding what the reference says.
struct HdrFlipOptions {
  std::optional<double> startExposure, stopExposure;  // in stops (factor 2^e)
  std::optional<int> exposures;                       // 1 or more
};

// The exposures HDR-FLIP evaluates: start, start + step, ..., stop with
// step = (stop - start) / (count - 1) (only start when count is 1).
struct FlipExposures {
  double start = 0, stop = 0;
  int count = 0;
};

// From the reference's luminance Y (Rec. 709 weights of its linear RGB,
// negative values taken as 0) and x85, the input the tone curve maps to
// 0.85:  start = log2(x85 / max Y), stop = log2(x85 / median Y),
// count = max(2, ceil(stop - start)) (less 1e-9 stops, so that rounding in
// the logarithms cannot add an exposure). Where half the pixels or more are
// black the median is that of the non-black pixels; an all-black reference
// has no brightness to place and gets start = stop = 0 (the images as they
// are, through the tone curve). Throws std::invalid_argument for a bad
// reference or options (start > stop, count < 1, a non-finite exposure).
FlipExposures hdrFlipExposures(const Image &reference, const HdrFlipOptions &o = {});

// HDR-FLIP of two linear-radiance images (negative values taken as 0): at
// each exposure e both are scaled by 2^e, tone mapped (ACES fit, clamped to
// [0, 1]) and compared by LDR-FLIP; the map is the per-pixel maximum. (The
// tone-mapped images are compared as the linear values their sRGB encoding
// decodes to; the encode-decode round trip is skipped as an identity.) Not
// symmetric: the exposures come from the reference. Throws as ldrFlip and
// hdrFlipExposures do.
FlipResult hdrFlip(const Image &test, const Image &reference, const FlipViewing &v = {},
                   const HdrFlipOptions &o = {});

// The map as a viewable 3-channel image of sRGB-encoded display values (for
// a PNG): matplotlib's "magma" colour map, which FLIP uses, interpolated
// linearly between 17 of its 256 entries (indices 0, 16, ..., 240, 255; the
// map is CC0), within 0.01 of the full table.
Image flipMapImage(const FlipResult &r);

// FLIP's stages, exposed for the tests. Colours are (R, G, B) linear sRGB,
// (X, Y, Z), (Y, Cx, Cz) with Y in [-16, 100], or (L*, a*, b*).
namespace flip {

using Color = std::array<double, 3>;

// The sRGB transfer curve (IEC 61966-2-1) both ways, the project's one
// (sampler/io/image_io.h).
using nuld::linearToSrgb;
using nuld::srgbToLinear;

Color linearRgbToXyz(const Color &rgb);
Color xyzToLinearRgb(const Color &xyz);
Color referenceWhite();  // XYZ of linear RGB (1, 1, 1)
Color xyzToYcxcz(const Color &xyz);
Color ycxczToXyz(const Color &ycxcz);
Color xyzToLab(const Color &xyz);
// a* and b* scaled by L* / 100 (the Hunt effect: colour fades in the dark).
inline Color huntAdjust(const Color &lab) {
  return {lab[0], 0.01 * lab[0] * lab[1], 0.01 * lab[0] * lab[2]};
}
// HyAB: |dL| + sqrt(da^2 + db^2), city block in lightness and Euclidean in
// chroma, a distance made for large colour differences (Abasi, Amani Tehran
// and Fairchild 2020).
inline double hyab(const Color &a, const Color &b) {
  const double da = a[1] - b[1], db = a[2] - b[2];
  return std::abs(a[0] - b[0]) + std::sqrt(da * da + db * db);
}
// cmax = hyab(Hunt(Lab(green)), Hunt(Lab(blue)))^qc.
double maxColorDifference();
// The colour error from hyab^qc: [0, pc cmax] maps linearly onto [0, pt],
// [pc cmax, cmax] onto [pt, 1].
double compressColorDifference(double poweredHyab);
// ACES fit with FLIP's coefficients, clamped to [0, 1]; finite for any x >= 0.
double toneMapAces(double x);
// The input x >= 0 that toneMapAces maps to `t` in (0, 1).
double acesInverse(double t);

// A separable kernel: one or more 1D factors whose outer products sum to
// the 2D kernel (the CSF's blue-yellow filter is a sum of two Gaussians).
struct SeparableKernel {
  int radius = 0;
  std::vector<std::vector<double>> factors;  // each 2 radius + 1 weights
};
enum class CsfChannel { Achromatic, RedGreen, BlueYellow };
SeparableKernel csfKernel(CsfChannel channel, double ppd);
// The feature detector's 1D factors (radius ceil(3 sigma)): the Gaussian
// (sum 1), its first derivative and its second (positive weights summing
// to 1, negative to -1).
struct FeatureKernels {
  int radius = 0;
  std::vector<double> gaussian, edge, point;
};
FeatureKernels featureKernels(double ppd);

// LDR-FLIP's two halves for two images in linear RGB (both clamped to
// [0, 1] first): the colour error (compressed), the feature error
// (max(edge, point difference) / sqrt 2)^qf, and FLIP = colour^(1 - feature).
struct Stages {
  int width = 0, height = 0;
  std::vector<float> color, feature, flip;
};
Stages ldrFlipLinear(const Image &testLinear, const Image &referenceLinear, double ppd);

}  // namespace flip
}  // namespace nuld
