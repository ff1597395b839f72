#pragma once
// An infinitely distant light from a lat-long HDR map. In the map's own
// frame row 0 is the zenith; by default the zenith is world +Y, column u = 0
// faces -Z and u = 1/4 faces +X. The map is then scaled, turned about its
// zenith by `rotation` degrees, and its zenith tilted to `up` (the shortest
// turn from +Y; for up = -Y the half-turn about +X), as pbrt's scenes give an
// infinite light a transform. A map stored upside down (most of its energy
// in the lower rows) is set right with up = (0, -1, 0).
//
// Sampling is the sampler module's `envmap:` target: the map's luminance as a
// piecewise-constant density whose rows are re-gridded to the equal-area v,
// which is exactly pbrt's luminance x sin(theta) distribution with sin(theta)
// integrated over each row; or, with PixelWeight::ChannelMean, its
// `envmap-mean:` target, the channels' mean in place of the luminance
// (pbrt-v4's and Cycles' choice: lower variance under coloured light); or
// either less its mean over the sphere (MIS compensation, for estimators
// that add BSDF samples by MIS; see image_targets.h). A compensated light
// also keeps its uncompensated twin: an estimator without BSDF samples (the
// light integrator) must sample the whole map, and compensation is a
// property of the MIS estimator, not of the map. Because the light samples
// *through the target*, a backend may hand over points already distributed by that target
// (optimized or neural sets) and the light uses them with the same pdf.

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "materials/rgb.h"
#include "materials/vec3.h"
#include "sampler/io/content_hash.h"
#include "sampler/io/image_io.h"
#include "sampler/targets/grid_target.h"
#include "sampler/targets/image_targets.h"

namespace nuld {

struct LightSample {
  Vec3 wi;       // world direction towards the light
  Rgb radiance;  // Le(wi)
  double pdf{};  // per unit solid angle
};

class EnvironmentLight {
 public:
  // `source` names the map in errors and in the target's spec (envmap:SOURCE).
  EnvironmentLight(Image latlong, double scale, double rotationDegrees, std::string source,
                   Vec3 up = {0, 1, 0}, PixelWeight weight = PixelWeight::Luminance);

  Rgb radiance(Vec3 worldDirection) const;
  // Density per unit solid angle of sampleTarget() / sample(); 0 for a black map.
  double pdf(Vec3 worldDirection) const;
  // Both at once (one cell lookup): what a path that escapes needs.
  Rgb radiance(Vec3 worldDirection, double &pdf) const;
  // The same lookup in two halves: find() locates the cell of a direction
  // and starts loading it, radiance(Lookup) reads it. A path finds the cell
  // of a ray before tracing it, so on a large map the cache miss overlaps
  // the traversal instead of following it.
  struct Lookup {
    const void *texel = nullptr;  // null: a black map
  };
  Lookup find(Vec3 worldDirection) const;
  Rgb radiance(Lookup lookup, double &pdf) const;

  // u uniform in [0,1)^2 -> a direction by inverse CDF; nullopt for a black map.
  std::optional<LightSample> sample(Point2 u) const;
  // x already distributed by target() -> the direction it stands for.
  std::optional<LightSample> sampleTarget(Point2 x) const;
  // Both for several points at once (out[k] for point k, the same values):
  // their reads of the tables overlap, so the cache misses of a large map
  // are paid about once per call rather than once per point.
  void sample(std::span<const Point2> u, std::span<std::optional<LightSample>> out) const;
  void sampleTarget(std::span<const Point2> x, std::span<std::optional<LightSample>> out) const;

  // The luminance of its radiance averaged over the sphere of directions
  // (each texel weighted by its solid angle); 0 for a black map.
  double meanLuminance() const;
  // The sampling density on the equal-area square; null when the map is black.
  const GridTarget *target() const { return target_.get(); }
  const std::string &source() const { return source_; }
  PixelWeight weight() const { return weight_; }
  // The same light sampled by the weight without compensation: *this when
  // the weight has none.
  const EnvironmentLight &uncompensated() const { return uncompensated_ ? *uncompensated_ : *this; }
  int width() const { return width_; }
  int height() const { return height_; }

  // Adds what the light's radiance and sampling depend on (its texels with
  // the scale applied, the weight, the turn and tilt) to `h`; the source's
  // name is left out, so the same map under two paths adds the same bytes.
  void hashContent(ContentHash &h) const;

  // Map-local direction (z = the map's up) <-> world direction.
  Vec3 toWorld(Vec3 local) const;
  Vec3 toLocal(Vec3 world) const;

 private:
  // A cell's radiance (scale applied); 12 bytes, so that the table of a
  // 1024 x 512 map is 6 MiB. Random directions read all of it, and the
  // smaller it is the more of it stays in cache: escaping rays and light
  // samples spent much of their time waiting for these reads. The pdf is
  // not stored: the target's density is the radiance's weight (luminance or
  // channel mean) over a constant, so pdfOf() recomputes it (to a few ulps of
  // the target's cellDensity(), and identically for radiance() and sample()).
  struct Texel {
    float rgb[3];
  };
  static_assert(sizeof(Texel) == 12);
  const Texel &texel(GridTarget::Cell c) const { return texels_[std::size_t(c.j) * width_ + c.i]; }
  static Rgb rgbOf(const Texel &t) { return {t.rgb[0], t.rgb[1], t.rgb[2]}; }
  double pdfOf(const Rgb &radiance) const {
    const double w = pixelWeight(radiance.r, radiance.g, radiance.b, weight_) - compensation_;
    return w > 0 ? w * pdfPerWeight_ : 0.0;
  }
  std::optional<LightSample> sampleCell(Point2 x, GridTarget::Cell c) const;

  int width_, height_;
  std::vector<Texel> texels_;  // row-major; empty for a black map
  PixelWeight weight_;
  double compensation_ = 0;  // the weight a compensated map subtracts (envmapCompensation)
  double pdfPerWeight_ = 0;  // solid-angle pdf of a cell / its (compensated) weight
  std::unique_ptr<GridTarget> target_;
  double cosRot_, sinRot_;  // the turn about the map's zenith
  bool tilted_;             // up is not +Y: tilt_ applies
  Vec3 tilt_[3];            // the world images of +X, +Y and +Z under the tilt to up
  std::string source_;
  // Null unless the weight is compensated; shared, so that copies stay cheap.
  std::shared_ptr<const EnvironmentLight> uncompensated_;
};

}  // namespace nuld
