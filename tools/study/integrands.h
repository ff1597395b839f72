#pragma once
// The integrands of `nuld study integrate` (the supplement's Fig. 2 and its
// BRDF / environment-map experiments, §3), each with the target that
// importance-samples it and an exact or converged reference value.
//
// Every integrand is written on the unit square: on the sphere and the
// hemisphere f(x) = 4 pi g(omega(x)), omega the equal-area map (docs/architecture.md,
// "Domains"),
// because d omega = 4 pi dx. Then the integral over the square is the
// integral of g over directions, and every sampler's estimate is the same
// (1/N) sum f(x_i) / p(x_i), p the target's density on the square.
//
// Directions live in the map-local frame of the environment map: +z is the
// map's zenith (row 0; world +Y for the renderer's EnvironmentLight), phi = 0
// is column u = 0. The BRDF's shading frame is that same frame (normal +z,
// tangent +x), i.e. a surface facing straight up, its tangent along u = 0.

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "materials/disney.h"
#include "materials/disney_target.h"
#include "materials/vec3.h"
#include "sampler/io/image_io.h"
#include "sampler/point.h"
#include "sampler/targets/grid_target.h"
#include "sampler/targets/target.h"
#include "sampler/targets/target_family.h"

namespace nuld::study {

struct Integrand {
  std::string name;  // the CSV's `integrand` value
  std::shared_ptr<const Target> target;
  std::function<double(Point2)> f;  // on the unit square (see above)
  double reference = 0;
  // An estimate of |reference - exact|: 0 for closed forms, the difference
  // between two quadrature resolutions otherwise.
  double referenceError = 0;
  std::string referenceMethod;
  // The BRDF's own sampling (the plain classic samplers on lobe integrands): u in [0,1)^2 -> g(w) /
  // pdf(w) for the direction w the BRDF's sample() makes of u, 0 when it
  // makes none. Empty for integrands without a BRDF.
  std::function<double(Point2)> lobeContribution;
  // For neural models of a target family (gamma > 0): the gamma under which
  // `family` yields this integrand's target, or nullopt. Empty: none does.
  std::function<std::optional<std::vector<double>>(const TargetFamily &)> familyGamma;

  Domain domain() const { return target->domain(); }
};

// The kinds --integrands accepts: gaussian*step, quarterdisc*bilinear,
// envmap*cos, disney*envmap and disney-grazing*envmap (these three once
// per environment map; the grazing one views the lobe from 89 degrees, a
// stability case) and disney*cosines (once per view angle, no map).
const std::vector<std::string> &integrandKinds();

// Target gaussian:0.5,0.5,0.15; f = p(x) [x.x < 0.6], so f / p is the step
// and the reference is the target's exact mass of [0, 0.6] x [0, 1]. The edge
// is off the mean and off every dyadic: at x0 = 0.5 any stratified set of
// 2^k points would integrate it exactly. Through the inverse CDF (a product
// map) the estimate counts the points with u.x below the step's mass, so a
// stratified set's error depends on where that mass cuts its strata: its
// RMSE need not fall monotonically between nearby N.
Integrand makeGaussianStep();

// Target quarterdisc (radius 1 about the origin, density 4 / pi);
// f = p(x) (a + b x + c y + d x y) with (a, b, c, d) = (0.25, 1, 0.5, 2).
// Reference in closed form: a + (4 / pi) ((b + c) / 3 + d / 8), from the
// disc's moments (integrals of x and y are 1/3, of x y 1/8).
Integrand makeQuarterDiscBilinear();

// An environment map as the study uses it: its luminance (clamped at 0, the
// same numbers as the `envmap:` target's density before normalization) and
// that target, whose cells are the map's pixels.
struct StudyEnvmap {
  std::string name;    // short name used in integrand names
  std::string source;  // the file; the target's spec is envmap:SOURCE
  int width = 0, height = 0;
  std::vector<double> luminance;  // row-major, row 0 = zenith
  std::shared_ptr<const GridTarget> target;

  // The luminance of the pixel holding x (a point of the equal-area square).
  double luminanceAt(Point2 x) const;
};

// Throws std::invalid_argument naming `source` for an all-black map.
std::shared_ptr<const StudyEnvmap> makeStudyEnvmap(const Image &latlong, std::string name,
                                                   std::string source);
std::shared_ptr<const StudyEnvmap> loadStudyEnvmap(const std::string &path, std::string name);

// The fixed normal of envmap*cos: 45 degrees from the map's zenith, towards
// phi = 90 degrees (u = 1/4), so its horizon cuts across pixels obliquely.
Vec3 envmapCosNormal();

// `envmap:NAME*cos`: g(w) = L(w) max(0, n . w), L the map's luminance,
// importance-sampled by the map's target. Reference: the sum over pixels of
// L times the integral of max(0, n . w) over the pixel, exact in phi and
// Gauss-Legendre in z = cos theta between the kinks (16 nodes; 8 give the
// error estimate).
Integrand makeEnvmapCos(std::shared_ptr<const StudyEnvmap> map, Vec3 normal = envmapCosNormal());

// `disney*envmap:NAME`: g(wi) = lum(f(wo, wi)) cos theta_i L(wi) on the upper
// hemisphere, for the supplement's instance (white, so f is grey and this is
// the luminance of the reflected radiance) and wo, with the map's luminance
// L. Importance-sampled by the tabulated `disney` target (what optimized and
// neural sets follow); lobeContribution gives the BRDF's own lobe sampling
// (one-sample MIS over lobes). Reference: per pixel, Gauss-Legendre 8 x 8 in
// (phi, z) over the pixel's part above the horizon, pixels of coarse maps
// split to at most 2 pi / 128 x 1 / 32 (4 x 4 gives the error estimate).
// `lobes` is how the BRDF's own sampling picks a lobe (materials/disney.h):
// it changes lobeContribution only, never the integrand or its target.
Integrand makeDisneyEnvmap(std::shared_ptr<const StudyEnvmap> map,
                           const DisneyParams &params = supplementDisneyParams(),
                           Vec3 wo = supplementWo(), LobeChoice lobes = kDefaultLobeChoice);

// `disney*cosines:theta=T`: the lobe of `params` at wo = (theta T, phi 0)
// against a smooth light, the mean of 8 clamped cosines max(0, n_k . wi)
// around fixed random normals (the kind of incident light diffuse
// interreflection gives): g(wi) = lum(f(wo, wi)) cos theta_i L(wi).
// Importance-sampled by the tabulated `disney` target at wo; the study makes
// one per disneyCosinesThetas(). Reference: Gauss-Legendre 6 x 6 on 256 x 128
// cells of (phi, cos theta) (3 x 3 gives the error estimate).
Integrand makeDisneyCosines(double thetaDegrees,
                            const DisneyParams &params = supplementDisneyParams(),
                            LobeChoice lobes = kDefaultLobeChoice);
std::vector<double> disneyCosinesThetas();
std::string disneyCosinesName(double thetaDegrees);
// disney-views*envmap: disney*envmap at the other views of disneyCosinesThetas
// (20 and 70 degrees, phi 0), named disney*envmap:MAP:theta=T.
std::vector<double> disneyViewThetas();
std::string disneyViewName(const std::string &map, double thetaDegrees);
std::vector<Vec3> smoothLightNormals();

// omega_o 89 degrees from the normal, in the plane of the tangent: the
// grazing view of disney-grazing*envmap.
Vec3 grazingWo();

// Gauss-Legendre nodes and weights on [-1, 1].
void gaussLegendre(int q, std::vector<double> &nodes, std::vector<double> &weights);

}  // namespace nuld::study
