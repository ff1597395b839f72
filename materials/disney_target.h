#pragma once
// A Disney BRDF lobe as a sampler target (docs/architecture.md,
// "Materials"): the hemisphere
// density proportional to luminance(f(wo, wi)) cos theta_i (or, with `mix`,
// blended with the material's own sampling pdf), tabulated on the
// equal-area sphere map (materials/sphere_map.h) as a GridTarget, so box
// masses are exact reads of its summed-area table.
//
// Layout: the grid covers the whole unit square (Domain::Hemisphere): phiCells
// uniform columns in u, thetaRows uniform rows over v in [0, 1/2] (the
// hemisphere), and one last zero-density row [1/2, 1] (the lower hemisphere).
// Rows are uniform in v, not refined toward the lobe, because the map is
// equal-area: every cell then covers the same solid angle 2 pi /
// (phiCells thetaRows), the table's resolution is the same in every
// direction, and the lobe's peak moves with wo anyway, so no fixed
// refinement would follow it. A cell's density is the average of f cos over
// 4 x 4 sub-cell midpoints; the map's Jacobian is constant (4 pi), so that
// average is the cell's mass over its area up to the normalization.
//
// Spec: `disney` or `disney:key=value,...` with keys basecolor (a grey value,
// or r/g/b), metallic, subsurface, specular, roughness, speculartint,
// anisotropic, sheen, sheentint, clearcoat, clearcoatgloss (all in [0, 1]),
// theta and phi (the polar and azimuthal angle of wo in degrees; theta in
// [0, 90)), res (phiCells), rows (thetaRows, default res / 2) and mix (the
// share of the material's own sampling pdf in the density, in [0, 1], default
// 0: see DisneyTargetSpec::samplingMix) and lobes (the material's lobe
// choice, default albedo: see LobeChoice). Keys left out take the supplement's instance
// (supplementDisneyParams) and wo at theta 45, phi 0.

#include <algorithm>
#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "materials/disney.h"
#include "materials/vec3.h"
#include "sampler/targets/grid_target.h"

namespace nuld {

// The supplement's test instance (§3): roughness .58, metallic .2, subsurface
// .5, anisotropic .15, base colour (1, 1, 1). "Other parameters are all zero"
// is taken literally: specular, specular tint, sheen, sheen tint, clearcoat
// and clearcoat gloss are 0 (so the dielectric specular F0 is 0 and the
// specular colour is metallic * base = 0.2).
DisneyParams supplementDisneyParams();
// The supplement's view direction (sqrt(2)/2, 0, sqrt(2)/2).
Vec3 supplementWo();

// What a `disney` target spec says.
struct DisneyTargetSpec {
  DisneyParams params = supplementDisneyParams();
  double thetaDegrees = 45, phiDegrees = 0;
  int phiCells = 256, thetaRows = 128;
  // 0: f cos; 1: the material's own sampling pdf (the lobe-selection
  // mapping's); between: the mixture of the two, each of mass one.
  double samplingMix = 0;
  // The material's own lobe choice, which its sampling pdf (mix > 0)
  // follows.
  LobeChoice lobeChoice = kDefaultLobeChoice;

  Vec3 wo() const;
  // rows when the spec names none: res / 2 (the hemisphere is half of the
  // map).
  int defaultRows() const { return std::max(1, phiCells / 2); }
  // Where its table lives.
  Domain domain() const { return Domain::Hemisphere; }
};

// Parses the part after `disney:` (empty for plain `disney`). Throws
// std::invalid_argument naming the spec, the key and what was expected.
DisneyTargetSpec parseDisneyTargetArgs(const std::string &args);
// The canonical spec: `disney`, plus every key that differs from the defaults.
std::string toSpec(const DisneyTargetSpec &spec);

// f(wo, .) cos theta of `params` tabulated as above. wo is normalized and
// must point above the surface. The 4 x 4 midpoint rule resolves lobes wider
// than a cell; sharper specular peaks alias. Measured at the default size
// and wo at 45 degrees, the total-variation distance between the table and
// the exact cell masses is 1.4e-5 for the supplement's instance and, for a
// metal, 2.3e-4 at roughness 0.2, 1.4e-3 at 0.1 and 8e-3 at 0.05.
std::unique_ptr<GridTarget> makeDisneyTarget(const DisneyParams &params, Vec3 wo,
                                             int phiCells = 256, int thetaRows = 128);
// The same from a parsed spec; the target reports toSpec(spec).
std::unique_ptr<GridTarget> makeDisneyTarget(const DisneyTargetSpec &spec);

// The `family:disney` gamma encoding of the view direction wo:
// gamma = (theta / 89 degrees, phi / 360 degrees), so gamma 1 is the most
// grazing view the family makes (as the materials tests cover).
inline constexpr double kDisneyFamilyMaxThetaDegrees = 89;
struct DisneyView {
  double thetaDegrees = 0, phiDegrees = 0;
};
// Forward: the view at gamma (entries in [0, 1], not checked).
DisneyView disneyFamilyView(std::array<double, 2> gamma);
// Inverse: the gamma of a view, phi taken modulo 360 (so phi 360, gamma 1,
// comes back as gamma 0: the same direction); nullopt unless theta is in
// [0, 89].
std::optional<std::array<double, 2>> invertDisneyFamilyView(DisneyView view);

// The gamma at which the target family `familySpec` (`family:disney[:ARGS]`
// or `family:disney-material[:ARGS]`) makes the `disney` target
// `targetSpec`: the same table layout (res, rows, mix), for
// family:disney the same material, and theta within the family's range.
// nullopt when the family makes no such target.
std::optional<std::vector<double>> disneyFamilyGamma(const std::string &familySpec,
                                                     const std::string &targetSpec);

// `family:disney-material[:res=..,rows=..,mix=..]`: one family for
// every Disney material, gamma = (theta / 89 degrees, phi / 360 degrees, base
// colour r, g, b, metallic, subsurface, specular, roughness, speculartint,
// anisotropic, sheen, sheentint, clearcoat, clearcoatgloss). A model trained
// on it serves any scene's lobe tables of its layout, with no per-scene
// setup. Gamma is drawn uniformly in training, so the map from gamma to a
// parameter has flat stretches where scenes put most materials: a quarter
// of gamma's range at each end of metallic (0 and 1), half of it at 0 for
// subsurface, the tints, anisotropic, sheen and clearcoat; the others are
// linear.
inline constexpr std::size_t kDisneyMaterialGammaDimension = 15;
// The spec the family makes at gamma (entries in [0, 1], 15 of them), with
// the layout of `layout`.
DisneyTargetSpec disneyMaterialSpec(const DisneyTargetSpec &layout, std::span<const double> gamma);
// The gamma of a spec's view and material (a parameter on a flat stretch
// maps to the stretch's middle); nullopt unless theta is in [0, 89].
std::optional<std::vector<double>> invertDisneyMaterialGamma(const DisneyTargetSpec &spec);

// Registers the `disney` kind of target (makeTarget) and the `family:disney`
// and `family:disney-material` target families (makeTargetFamily).
void registerMaterialTargets();

}  // namespace nuld
