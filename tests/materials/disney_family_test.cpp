// The `family:disney` target family: gamma = (theta / 89 degrees, phi / 360 degrees) of wo.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "materials/disney_target.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/target_family.h"
#include "sampler/targets/target_spec.h"

namespace nuld {
namespace {

TEST(DisneyFamily, GammaSelectsTheViewDirection) {
  registerMaterialTargets();
  const auto family = makeTargetFamily("family:disney:res=32");
  EXPECT_EQ(family->gammaDimension(), 2u);
  EXPECT_EQ(family->domain(), Domain::Hemisphere);
  EXPECT_EQ(makeTargetFamily(family->spec())->spec(), family->spec());
  const auto gamma45 = invertDisneyFamilyView({45, 0});
  ASSERT_TRUE(gamma45);
  const auto a = family->target(std::vector<double>{(*gamma45)[0], (*gamma45)[1]});
  const auto b = makeTarget("disney:theta=45,res=32");
  // The same table as the plain spec with that view.
  for (double u = 0.05; u < 1; u += 0.1)
    for (double v = 0.02; v < 0.5; v += 0.05) EXPECT_DOUBLE_EQ(a->pdf({u, v}), b->pdf({u, v}));
  // Grazing (gamma 1 = 89 degrees) is still a proper density.
  const auto grazing = family->target(std::vector<double>{1, 0.3});
  EXPECT_NEAR(grazing->mass({{0, 0}, {1, 1}}), 1, 1e-12);
  EXPECT_THROW(makeTargetFamily("family:disney:theta=30"), std::invalid_argument);
  EXPECT_THROW(family->target(std::vector<double>{0.5}), std::invalid_argument);
}

// Forward then inverse gives gamma back, up to rounding; phi's gamma 1 is
// phi 360, the same direction as gamma 0, and comes back as 0.
TEST(DisneyFamily, GammaOfTheViewInvertsTheView) {
  const std::array<double, 2> gammas[] = {{0, 0},         {1, 0},     {0, 0.5},
                                          {45.0 / 89, 0}, {1, 0.5},   {0.25, 0.75},
                                          {1e-12, 0},     {1, 0.999}, {0.5, 1e-9}};
  for (const auto &g : gammas) {
    const DisneyView view = disneyFamilyView(g);
    const auto back = invertDisneyFamilyView(view);
    ASSERT_TRUE(back) << g[0] << " " << g[1];
    EXPECT_DOUBLE_EQ((*back)[0], g[0]);
    EXPECT_DOUBLE_EQ((*back)[1], g[1]);
  }
  const DisneyView grazing = disneyFamilyView({1, 1});
  EXPECT_EQ(grazing.thetaDegrees, kDisneyFamilyMaxThetaDegrees);
  EXPECT_EQ(grazing.phiDegrees, 360);
  const auto wrapped = invertDisneyFamilyView(grazing);
  ASSERT_TRUE(wrapped);
  EXPECT_EQ((*wrapped)[0], 1);
  EXPECT_EQ((*wrapped)[1], 0);
}

// Inverse then forward gives the view back with phi in [0, 360); views the
// family does not make (theta outside [0, 89]) have no gamma.
TEST(DisneyFamily, ViewOfTheGammaInvertsTheGamma) {
  struct Case {
    DisneyView view;
    double phiBack;
  };
  const Case cases[] = {
      {{0, 0}, 0},      {{89, 0}, 0},   {{45, 0}, 0},       {{30, 90}, 90},
      {{30, -90}, 270}, {{10, 360}, 0}, {{10, 720.5}, 0.5}, {{88.999, 359.9}, 359.9}};
  for (const Case &c : cases) {
    const auto gamma = invertDisneyFamilyView(c.view);
    ASSERT_TRUE(gamma) << c.view.thetaDegrees << " " << c.view.phiDegrees;
    EXPECT_GE((*gamma)[0], 0);
    EXPECT_LE((*gamma)[0], 1);
    EXPECT_GE((*gamma)[1], 0);
    EXPECT_LT((*gamma)[1], 1);
    const DisneyView back = disneyFamilyView(*gamma);
    EXPECT_NEAR(back.thetaDegrees, c.view.thetaDegrees, 1e-12);
    EXPECT_NEAR(back.phiDegrees, c.phiBack, 1e-12);
  }
  EXPECT_EQ(disneyFamilyView(*invertDisneyFamilyView({89, 0})).thetaDegrees, 89);
  for (const double theta : {89.0001, 90.0, -1e-9, std::numeric_limits<double>::quiet_NaN()})
    EXPECT_FALSE(invertDisneyFamilyView({theta, 0})) << theta;
}

// A spec's gamma (disneyFamilyGamma, the backends' and studies' way in) is
// the view's inverse.
TEST(DisneyFamily, SpecGammaIsTheViewsInverse) {
  registerMaterialTargets();
  const auto family = makeTargetFamily("family:disney:res=32");
  const auto g = disneyFamilyGamma(family->spec(), "disney:theta=60,phi=300,res=32");
  ASSERT_TRUE(g);
  const auto view = *invertDisneyFamilyView({60, 300});
  EXPECT_EQ(*g, (std::vector<double>{view[0], view[1]}));
  EXPECT_FALSE(disneyFamilyGamma(family->spec(), "disney:theta=89.5,res=32"));
  // The tables' density is part of the family: a model trained on f cos does
  // not serve the MIS tables (mix 1), one trained on family:disney:mix=1 does.
  EXPECT_FALSE(disneyFamilyGamma(family->spec(), "disney:theta=60,res=32,mix=1"));
  const auto sampling = makeTargetFamily("family:disney:res=32,mix=1");
  EXPECT_EQ(sampling->spec(), "family:disney:res=32,mix=1");
  EXPECT_TRUE(disneyFamilyGamma(sampling->spec(), "disney:theta=60,res=32,mix=1"));
  EXPECT_FALSE(disneyFamilyGamma(sampling->spec(), "disney:theta=60,res=32"));
  const std::array<double, 2> gamma{0.5, 0.25};
  EXPECT_NE(sampling->target(gamma)->spec().find("mix=1"), std::string::npos);
}

// family:disney-material: gamma covers the view and the whole material.
// A gamma off the flat stretches comes back from the spec it makes; the
// scenes' usual values (metallic 0 and 1, no clear coat) sit on the flats
// and come back as their middles; a renderer's lobe table of a scene
// material (under MIS: 64 x 32 cells, mix 1) is one of the family's targets, the same table; keys
// other than the layout are refused.
TEST(DisneyFamily, MaterialFamilyCoversEveryMaterial) {
  registerMaterialTargets();
  const auto family = makeTargetFamily("family:disney-material:res=64,rows=32,mix=1");
  EXPECT_EQ(family->spec(), "family:disney-material:res=64,mix=1");  // rows 32 is res / 2
  EXPECT_EQ(family->gammaDimension(), kDisneyMaterialGammaDimension);
  EXPECT_EQ(family->domain(), Domain::Hemisphere);
  Rng rng(8);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<double> gamma(kDisneyMaterialGammaDimension);
    for (double &g : gamma) g = rng.uniform();
    const auto target = family->target(gamma);
    const auto back = disneyFamilyGamma(family->spec(), target->spec());
    ASSERT_TRUE(back) << target->spec();
    // Round trip through the spec's printed numbers: the same target.
    EXPECT_EQ(family->target(*back)->spec(), target->spec());
  }
  // A scene's material: the cup (scenes/cup.json), its table at a bin.
  DisneyTargetSpec cup;
  cup.params = DisneyParams{};
  cup.params.baseColor = {0.92, 0.9, 0.86};
  cup.params.roughness = 0.15;
  cup.params.specular = 0.5;
  cup.params.clearcoat = 1;
  cup.params.clearcoatGloss = 0.9;
  cup.thetaDegrees = 45;
  cup.phiDegrees = 0;
  cup.phiCells = 64;
  cup.thetaRows = 32;
  cup.samplingMix = 1;
  const auto g = disneyFamilyGamma(family->spec(), toSpec(cup));
  ASSERT_TRUE(g);
  EXPECT_EQ((*g)[5], 0.125);  // metallic 0: the middle of its flat quarter
  EXPECT_EQ((*g)[13], 1.0);   // clearcoat 1: the top of its linear half
  const auto made = family->target(*g);
  const auto direct = makeDisneyTarget(cup);
  EXPECT_EQ(made->contentHash(), direct->contentHash());
  // Another layout is another family's.
  cup.samplingMix = 0;
  EXPECT_FALSE(disneyFamilyGamma(family->spec(), toSpec(cup)));
  EXPECT_THROW(makeTargetFamily("family:disney-material:roughness=0.5"), std::invalid_argument);
}

}  // namespace
}  // namespace nuld
