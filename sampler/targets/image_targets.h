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
// (tools/experiments/cycles_crosscheck.md).

#include <memory>
#include <string>

#include "sampler/enum_names.h"
#include "sampler/io/image_io.h"
#include "sampler/targets/grid_target.h"

namespace nuld {

// How a pixel's colour becomes density (negative values count as 0). The
// compensated weights of an environment map also subtract the map's mean
// weight over the sphere, clamped at 0: MIS compensation (Karlik et al.
// 2019), for renderers that combine the light's samples with BSDF samples
// by multiple importance sampling. The BSDF samples cover the directions
// dimmer than average, where the light then places none, and the light's
// samples go to the bright part that matters. A map with no pixel above its
// mean (a constant one) keeps its plain weight.
enum class PixelWeight { Luminance, ChannelMean, LuminanceCompensated, ChannelMeanCompensated };
// Their names where a scene file or a command names one ("importance").
inline constexpr auto kImportanceNames = enumTable<PixelWeight>(
    "importance", {{"luminance", PixelWeight::Luminance},
                   {"mean", PixelWeight::ChannelMean},
                   {"luminance-compensated", PixelWeight::LuminanceCompensated},
                   {"mean-compensated", PixelWeight::ChannelMeanCompensated}});
constexpr const auto &enumNames(PixelWeight) { return kImportanceNames; }
bool isCompensated(PixelWeight weight);
// The weight without its compensation (Luminance for LuminanceCompensated;
// the weight itself when it has none).
PixelWeight uncompensated(PixelWeight weight);
// A pixel's weight before any compensation.
double pixelWeight(double r, double g, double b, PixelWeight weight);
// The weight a compensated map subtracts from every pixel (its mean over
// the sphere); 0 for the other weights and for maps it would leave black.
double envmapCompensation(const Image &latlong, PixelWeight weight);
// The spec family of an environment map weighted so: envmap, envmap-mean,
// envmap-compensated or envmap-mean-compensated.
const char *envmapFamily(PixelWeight weight);

std::unique_ptr<GridTarget> makeImageTarget(const Image &image, const std::string &source);
// `compensation`, when given, receives the weight the target subtracted
// (envmapCompensation), so that a light can evaluate the same density.
std::unique_ptr<GridTarget> makeEnvmapTarget(const Image &latlong, const std::string &source,
                                             PixelWeight weight = PixelWeight::Luminance,
                                             double *compensation = nullptr);

std::unique_ptr<GridTarget> loadImageTarget(const std::string &path);
std::unique_ptr<GridTarget> loadEnvmapTarget(const std::string &path,
                                             PixelWeight weight = PixelWeight::Luminance);

}  // namespace nuld
