// Tests of the Disney lobe as a sampler target (materials/disney_target.h):
// its layout and mass, the tabulated density against f cos / albedo, its
// inverse-CDF samples against the lobe, and the `disney` spec family.

#include "materials/disney_target.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "materials/sphere_map.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/target_family.h"
#include "sampler/targets/target_spec.h"
#include "tests/materials/chi_square.h"
#include "tests/materials/quadrature.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;

// luminance(f) cos theta_i as a density on the square (per unit (u, v) area,
// 4 pi per steradian), unnormalized.
test::Integrand lobeOnSquare(const DisneyBrdf &brdf, Vec3 wo) {
  return [&brdf, wo](Point2 p) {
    const Vec3 wi = sphereDirection(p);
    return 4 * kPi * brdf.eval(wo, wi).luminance() * std::max(0.0, wi.z);
  };
}

// The exact mass of every cell of `t` (hemisphere rows only), and the
// normalization: the albedo, integral of luminance(f) cos over wi.
std::vector<double> exactCellMasses(const GridTarget &t, const DisneyBrdf &brdf, Vec3 wo,
                                    double *albedo) {
  const std::vector<double> yEdges(t.yEdges().begin(), t.yEdges().end() - 1);
  auto cells = test::integrateCells(lobeOnSquare(brdf, wo), t.xEdges(), yEdges,
                                    test::peakAt(reflect(wo, Vec3{0, 0, 1})));
  double total = 0;
  for (double c : cells) total += c;
  for (double &c : cells) c /= total;
  *albedo = total;
  return cells;
}

TEST(DisneyTarget, LayoutAndMass) {
  const auto t = makeDisneyTarget(supplementDisneyParams(), supplementWo(), 64, 32);
  EXPECT_EQ(t->domain(), Domain::Hemisphere);
  ASSERT_EQ(t->cols(), 64);
  ASSERT_EQ(t->rows(), 33);
  EXPECT_EQ(t->yEdges()[32], 0.5);
  EXPECT_EQ(t->yEdges()[33], 1.0);
  EXPECT_NEAR(t->mass({{0, 0}, {1, 1}}), 1, 1e-12);
  EXPECT_NEAR(t->mass({{0, 0}, {1, 0.5}}), 1, 1e-12);
  EXPECT_EQ(t->mass({{0, 0.5}, {1, 1}}), 0);
  Rng rng(61);
  for (int k = 0; k < 1000; ++k) {
    EXPECT_EQ(t->pdf({rng.uniform(), 0.5 + 1e-9 + 0.5 * rng.uniform()}), 0);
    EXPECT_LE(t->invert({rng.uniform(), rng.uniform()}).x.y, 0.5);
  }
}

// Each cell holds the lobe's exact mass over it up to the 4 x 4 midpoint
// rule's error, and its density at the centre is f cos / albedo up to the
// lobe's variation across one cell.
TEST(DisneyTarget, TabulationMatchesTheLobe) {
  struct Case {
    DisneyParams params;
    Vec3 wo;
    double maxTotalVariation;
  };
  DisneyParams glossy = supplementDisneyParams();
  glossy.roughness = 0.3;
  const std::vector<Case> cases = {{supplementDisneyParams(), supplementWo(), 1e-4},
                                   {glossy, normalize(Vec3{0.5, 0.2, 0.3}), 1e-3}};
  for (const Case &c : cases) {
    const DisneyBrdf brdf(c.params);
    const auto t = makeDisneyTarget(c.params, c.wo, 128, 64);
    double albedo = 0;
    const auto exact = exactCellMasses(*t, brdf, c.wo, &albedo);
    double totalVariation = 0, maxCentreError = 0;
    const auto lobe = lobeOnSquare(brdf, c.wo);
    for (int j = 0; j < 64; ++j)
      for (int i = 0; i < 128; ++i) {
        const double area =
            (t->xEdges()[i + 1] - t->xEdges()[i]) * (t->yEdges()[j + 1] - t->yEdges()[j]);
        totalVariation += 0.5 * std::abs(t->cellDensity(i, j) * area - exact[j * 128 + i]);
        const Point2 centre{0.5 * (t->xEdges()[i] + t->xEdges()[i + 1]),
                            0.5 * (t->yEdges()[j] + t->yEdges()[j + 1])};
        const double expected = lobe(centre) / albedo;
        maxCentreError =
            std::max(maxCentreError, std::abs(t->pdf(centre) - expected) / std::max(expected, 1.0));
      }
    std::cout << "[ info ] " << t->spec() << ": albedo " << albedo << ", total variation "
              << totalVariation << ", max centre error " << maxCentreError << "\n";
    EXPECT_LT(totalVariation, c.maxTotalVariation) << t->spec();
    EXPECT_LT(maxCentreError, 0.05) << t->spec();
  }
}

// Inverse-CDF points of the target, mapped to directions, follow
// luminance(f) cos / albedo (coarse bins: the tabulation error is far below
// the statistical resolution there).
TEST(DisneyTarget, InvertedSamplesFollowTheLobe) {
  const DisneyParams params = supplementDisneyParams();
  const Vec3 wo = supplementWo();
  const DisneyBrdf brdf(params);
  const auto t = makeDisneyTarget(params, wo);
  double albedo = 0;
  exactCellMasses(*makeDisneyTarget(params, wo, 8, 4), brdf, wo, &albedo);
  const auto r = test::testDirections(
      [&](Point2 u) -> std::optional<Vec3> { return sphereDirection(t->invert(u).x); },
      [&](Vec3 wi) { return brdf.eval(wo, wi).luminance() * std::max(0.0, wi.z) / albedo; }, 300000,
      62, test::peakAt(reflect(wo, Vec3{0, 0, 1})), 32, 16);
  EXPECT_GT(r.chi.pValue, test::sidakLevel()) << r.describe();
  EXPECT_NEAR(r.pdfMass, 1, 1e-6);
}

// mix = 1 tabulates the material's own sampling pdf: inverse-CDF points of
// the table, mapped to directions, follow DisneyBrdf::pdf (chi-square), for
// a clear-coated glaze whose peaks the mix exists for; mix = 1/2 is the
// cell-by-cell average of the two tables, each of mass one.
TEST(DisneyTarget, MixTabulatesTheSamplingPdf) {
  DisneyParams glaze;
  glaze.baseColor = {0.92, 0.9, 0.86};
  glaze.roughness = 0.3;
  glaze.clearcoat = 1;
  glaze.clearcoatGloss = 0.5;
  DisneyTargetSpec spec;
  spec.params = glaze;
  spec.thetaDegrees = 30;
  spec.samplingMix = 1;
  const DisneyBrdf brdf(glaze);
  const Vec3 wo = spec.wo();
  const auto sampling = makeDisneyTarget(spec);
  EXPECT_EQ(sampling->spec(), toSpec(spec));
  EXPECT_NE(sampling->spec().find("mix=1"), std::string::npos);
  // The sampling pdf loses the mass of the microfacet samples that land
  // below the surface; the table holds it renormalized over the hemisphere.
  double mass = 1;
  for (int pass = 0; pass < 2; ++pass) {
    const auto r = test::testDirections(
        [&](Point2 u) -> std::optional<Vec3> { return sphereDirection(sampling->invert(u).x); },
        [&](Vec3 wi) { return wi.z > 0 ? brdf.pdf(wo, wi) / mass : 0.0; }, 300000, 63,
        test::peakAt(reflect(wo, Vec3{0, 0, 1})), 32, 16);
    if (pass == 0) {
      EXPECT_GT(r.pdfMass, 0.9);
      mass = r.pdfMass;
    } else {
      EXPECT_GT(r.chi.pValue, test::sidakLevel()) << r.describe();
      EXPECT_NEAR(r.pdfMass, 1, 1e-6);
    }
  }

  spec.samplingMix = 0;
  const auto product = makeDisneyTarget(spec);
  spec.samplingMix = 0.5;
  const auto half = makeDisneyTarget(spec);
  for (int j = 0; j < 128; j += 3)
    for (int i = 0; i < 256; i += 5)
      EXPECT_NEAR(half->cellDensity(i, j),
                  0.5 * (product->cellDensity(i, j) + sampling->cellDensity(i, j)),
                  1e-12 * (1 + half->cellDensity(i, j)))
          << i << " " << j;
}

// ------------------------------------------------------------------- specs

TEST(DisneyTargetSpec, DefaultsAreTheSupplementInstance) {
  const DisneyTargetSpec s = parseDisneyTargetArgs("");
  EXPECT_EQ(s.params, supplementDisneyParams());
  EXPECT_EQ(s.params.roughness, 0.58);
  EXPECT_EQ(s.params.metallic, 0.2);
  EXPECT_EQ(s.params.subsurface, 0.5);
  EXPECT_EQ(s.params.anisotropic, 0.15);
  EXPECT_EQ(s.params.specular, 0);  // "other parameters are all zero"
  EXPECT_EQ(s.params.baseColor, Rgb::grey(1));
  EXPECT_EQ(s.phiCells, 256);
  EXPECT_EQ(s.thetaRows, 128);
  const Vec3 wo = s.wo();
  EXPECT_NEAR(wo.x, std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(wo.y, 0, 1e-15);
  EXPECT_NEAR(wo.z, std::sqrt(0.5), 1e-15);
  EXPECT_EQ(toSpec(s), "disney");
}

TEST(DisneyTargetSpec, EveryKeyParsesAndRoundTrips) {
  const DisneyTargetSpec s = parseDisneyTargetArgs(
      "basecolor=0.5,metallic=0.1,subsurface=0.2,specular=0.3,roughness=0.4,speculartint=0.5,"
      "anisotropic=0.6,sheen=0.7,sheentint=0.8,clearcoat=0.9,clearcoatgloss=1,theta=30,phi=-90,"
      "res=64,mix=0.25");
  EXPECT_EQ(s.params.baseColor, Rgb::grey(0.5));
  EXPECT_EQ(s.params.metallic, 0.1);
  EXPECT_EQ(s.params.subsurface, 0.2);
  EXPECT_EQ(s.params.specular, 0.3);
  EXPECT_EQ(s.params.roughness, 0.4);
  EXPECT_EQ(s.params.specularTint, 0.5);
  EXPECT_EQ(s.params.anisotropic, 0.6);
  EXPECT_EQ(s.params.sheen, 0.7);
  EXPECT_EQ(s.params.sheenTint, 0.8);
  EXPECT_EQ(s.params.clearcoat, 0.9);
  EXPECT_EQ(s.params.clearcoatGloss, 1);
  EXPECT_EQ(s.thetaDegrees, 30);
  EXPECT_EQ(s.phiDegrees, -90);
  EXPECT_EQ(s.phiCells, 64);
  EXPECT_EQ(s.thetaRows, 32);
  EXPECT_EQ(s.samplingMix, 0.25);
  const std::string spec = toSpec(s);
  const auto again = parseDisneyTargetArgs(spec.substr(spec.find(':') + 1));
  EXPECT_EQ(again.params, s.params);
  EXPECT_EQ(toSpec(again), spec);

  const auto colour = parseDisneyTargetArgs("basecolor=0.1/0.2/0.3,rows=7,res=16");
  EXPECT_EQ(colour.params.baseColor, (Rgb{0.1, 0.2, 0.3}));
  EXPECT_EQ(colour.thetaRows, 7);
  EXPECT_EQ(toSpec(colour), "disney:basecolor=0.1/0.2/0.3,res=16,rows=7");
}

void expectError(const std::string &spec, const std::vector<std::string> &mentions) {
  registerMaterialTargets();
  try {
    makeTarget(spec);
    ADD_FAILURE() << spec << ": expected std::invalid_argument";
  } catch (const std::invalid_argument &e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'" + spec + "'"), std::string::npos) << what;
    for (const auto &m : mentions)
      EXPECT_NE(what.find(m), std::string::npos) << m << " in " << what;
  }
}

TEST(DisneyTargetSpec, BadArgumentsNameSpecKeyAndExpectation) {
  expectError("disney:shininess=1", {"unknown key 'shininess'", "roughness", "clearcoatgloss"});
  expectError("disney:roughness=abc", {"'abc' is not a number", "roughness"});
  expectError("disney:roughness=", {"'roughness' has no value"});
  expectError("disney:roughness=1.5", {"roughness = 1.5", "[0, 1]"});
  expectError("disney:metallic=-0.1", {"metallic", "[0, 1]"});
  expectError("disney:theta=90", {"theta", "[0, 90)"});
  expectError("disney:res=0", {"res", "integer"});
  expectError("disney:mix=2", {"mix = 2", "[0, 1]"});
  expectError("disney:res=10.5", {"res", "integer"});
  expectError("disney:roughness", {"'roughness' is not key=value"});
  expectError("disney:roughness=0.1,roughness=0.2", {"'roughness' is given twice"});
  expectError("disney:basecolor=0.1/0.2", {"basecolor", "r/g/b"});
  expectError("disney:roughness=0.1,", {"'' is not key=value"});
  expectError("disney:space=sphere", {"unknown key 'space'"});
  EXPECT_THROW(makeDisneyTarget(supplementDisneyParams(), {0, 0.6, -0.8}), std::invalid_argument);
}

// `lobes=` names the material's lobe choice (which the tables' sampling pdf
// follows) and round-trips; rows default to res / 2.
TEST(DisneyTargetSpec, LobeChoiceKeyAndDefaultRows) {
  registerMaterialTargets();
  const auto metal = makeTarget("disney:metallic=1,roughness=0.2,res=12,lobes=uniform");
  EXPECT_EQ(metal->spec(), "disney:metallic=1,roughness=0.2,res=12,lobes=uniform");
  EXPECT_EQ(parseDisneyTargetArgs("lobes=weight").lobeChoice, LobeChoice::Weight);
  EXPECT_EQ(parseDisneyTargetArgs("").lobeChoice, kDefaultLobeChoice);
  EXPECT_THROW(parseDisneyTargetArgs("lobes=random"), std::invalid_argument);
  EXPECT_EQ(metal->domain(), Domain::Hemisphere);
  EXPECT_EQ(parseDisneyTargetArgs("res=12").thetaRows, 6);
}

TEST(DisneyTargetSpec, RegisteredWithMakeTarget) {
  registerMaterialTargets();
  const auto fromSpec = makeTarget("disney");
  const auto bare = makeTarget("disney:");
  const auto direct = makeDisneyTarget(supplementDisneyParams(), supplementWo());
  EXPECT_EQ(fromSpec->spec(), "disney");
  EXPECT_EQ(bare->spec(), "disney");
  EXPECT_EQ(direct->spec(), "disney");
  EXPECT_EQ(fromSpec->domain(), Domain::Hemisphere);
  Rng rng(63);
  for (int k = 0; k < 2000; ++k) {
    const Point2 p{rng.uniform(), rng.uniform()};
    EXPECT_NEAR(fromSpec->pdf(p), direct->pdf(p), 1e-12 * (1 + direct->pdf(p)));
    EXPECT_EQ(fromSpec->pdf(p), bare->pdf(p));
  }
  const auto small = makeTarget("disney:roughness=0.3,res=32");
  EXPECT_EQ(small->spec(), "disney:roughness=0.3,res=32");
  const auto *grid = dynamic_cast<const GridTarget *>(small.get());
  ASSERT_NE(grid, nullptr);
  EXPECT_EQ(grid->cols(), 32);
  EXPECT_EQ(grid->rows(), 17);
  EXPECT_EQ(makeTarget(small->spec())->spec(), small->spec());
}

}  // namespace
}  // namespace nuld
