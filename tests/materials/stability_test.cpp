// Numerical stability of the materials: roughness 0 and 1, alpha extremes,
// grazing, horizon and back-facing directions, and u on the edges of
// [0,1)^2 must never produce NaN or infinity from eval, pdf or sample.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "materials/disney.h"
#include "materials/microfacet.h"
#include "sampler/sequences/rng.h"
#include "tests/materials/directions.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;
const double kJustBelowOne = std::nextafter(1.0, 0.0);

using test::fromAngles;

// Views from the normal to (and past) the horizon.
std::vector<Vec3> views() {
  std::vector<Vec3> v;
  for (const double theta : {0.0, 1e-6, 45.0, 89.0, 89.9, 89.99, 89.999})
    for (const double phi : {0.0, 37.0, 90.0}) v.push_back(fromAngles(theta, phi));
  v.push_back(normalize(Vec3{1, 0, 1e-12}));
  return v;
}
std::vector<Vec3> nonReflectingViews() {
  return {{1, 0, 0}, {0, 1, 0}, {0.6, 0, -0.8}, {0, 0, -1}, normalize(Vec3{1, 1, -1e-12})};
}

// u on the edges of the unit square and a few interior values.
std::vector<Point2> edgeUs() {
  const std::vector<double> values = {0.0,     1e-12, 0.25,      1.0 / 3,      0.5,
                                      2.0 / 3, 0.75,  1 - 1e-12, kJustBelowOne};
  std::vector<Point2> us;
  for (const double a : values)
    for (const double b : values) us.push_back({a, b});
  return us;
}

std::vector<std::pair<std::string, DisneyParams>> extremeParams() {
  std::vector<std::pair<std::string, DisneyParams>> out;
  for (const double r : {0.0, 1e-3, 1.0})
    for (const double a : {0.0, 1.0})
      for (const double m : {0.0, 1.0}) {
        DisneyParams p;
        p.roughness = r;
        p.anisotropic = a;
        p.metallic = m;
        p.subsurface = 1 - m;
        p.sheen = 1;
        p.clearcoat = r == 0 ? 1 : 0;
        p.clearcoatGloss = 1;
        out.push_back({"roughness " + std::to_string(r) + " anisotropic " + std::to_string(a) +
                           " metallic " + std::to_string(m),
                       p});
      }
  DisneyParams black;
  black.baseColor = Rgb::grey(0);
  black.specular = 0;
  out.push_back({"black", black});
  return out;
}

TEST(Stability, DisneyIsFiniteEverywhere) {
  Rng rng(51);
  const auto us = edgeUs();
  for (const auto &[name, params] : extremeParams()) {
    const DisneyBrdf brdf(params);
    for (const Vec3 wo : views()) {
      for (const Point2 u : us) {
        const auto s = brdf.sampleSquare(wo, u);
        if (!s) continue;
        ASSERT_TRUE(s->f.isFinite()) << name;
        ASSERT_TRUE(std::isfinite(s->pdf) && s->pdf > 0) << name;
        ASSERT_TRUE(isFinite(s->wi) && s->wi.z > 0) << name;
        ASSERT_NEAR(length(s->wi), 1, 1e-9) << name;
      }
      for (int k = 0; k < 200; ++k) {
        // Directions everywhere, the horizon and the lower hemisphere included.
        const double z = 2 * rng.uniform() - 1, phi = 2 * kPi * rng.uniform();
        const double r = std::sqrt(1 - z * z);
        for (const Vec3 wi : {Vec3{r * std::cos(phi), r * std::sin(phi), z},
                              Vec3{std::cos(phi), std::sin(phi), 0}, reflect(wo, {0, 0, 1})}) {
          const Rgb f = brdf.eval(wo, wi);
          const double pdf = brdf.pdf(wo, wi);
          ASSERT_TRUE(f.isFinite()) << name;
          ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0) << name;
          if (!(wi.z > 0)) {
            ASSERT_TRUE(f.isBlack()) << name;
            ASSERT_EQ(pdf, 0) << name;
          }
          for (int l = 0; l < brdf.lobeCount(); ++l) {
            ASSERT_TRUE(brdf.evalLobe(l, wo, wi).isFinite()) << name;
            ASSERT_TRUE(std::isfinite(brdf.lobePdf(l, wo, wi))) << name;
          }
        }
      }
    }
    for (const Vec3 wo : nonReflectingViews()) {
      for (const Point2 u : us) ASSERT_FALSE(brdf.sampleSquare(wo, u)) << name;
      for (int l = 0; l < brdf.lobeCount(); ++l) ASSERT_FALSE(brdf.sampleLobe(l, wo, {0.5, 0.5}));
      const Vec3 wi = normalize(Vec3{0.1, 0.2, 0.9});
      EXPECT_TRUE(brdf.eval(wo, wi).isBlack()) << name;
      EXPECT_TRUE(brdf.eval(wi, wo).isBlack()) << name;
      EXPECT_EQ(brdf.pdf(wo, wi), 0) << name;
      EXPECT_EQ(brdf.pdf(wi, wo), 0) << name;
    }
  }
}

// The mirror direction at roughness 0: the sharpest value the model produces
// stays finite, and the pdf there is large but finite.
TEST(Stability, RoughnessZeroMirrorPeakIsFinite) {
  DisneyParams p;
  p.roughness = 0;
  p.metallic = 1;
  const DisneyBrdf brdf(p);
  for (const Vec3 wo : views()) {
    const Vec3 mirror = reflect(wo, {0, 0, 1});
    const Rgb f = brdf.eval(wo, mirror);
    const double pdf = brdf.pdf(wo, mirror);
    EXPECT_TRUE(f.isFinite());
    EXPECT_TRUE(std::isfinite(pdf));
    EXPECT_GT(pdf, 1e5);  // a sharp lobe: alpha at its floor
  }
}

TEST(Stability, MicrofacetAlphaExtremes) {
  const auto us = edgeUs();
  for (const double ax : {0.0, 1e-4, 1.0, 3.2})
    for (const double ay : {0.0, 0.3, 3.2}) {
      const GgxDistribution d(ax, ay);
      for (const Vec3 wo : views()) {
        EXPECT_TRUE(std::isfinite(d.G1(wo)));
        EXPECT_TRUE(std::isfinite(d.lambda(wo)));
        for (const Point2 u : us) {
          const Vec3 m = d.sampleVisibleNormal(wo, u);
          ASSERT_TRUE(isFinite(m)) << ax << " " << ay;
          ASSERT_GE(m.z, 0);
          ASSERT_TRUE(std::isfinite(d.D(m)));
          ASSERT_TRUE(std::isfinite(d.visibleD(wo, m)));
          if (const auto wi = d.sampleReflection(wo, u)) {
            ASSERT_GT(wi->z, 0);
            ASSERT_TRUE(std::isfinite(d.reflectionPdf(wo, *wi)));
            ASSERT_TRUE(std::isfinite(d.visibility(wo, *wi)));
          }
        }
      }
      EXPECT_EQ(d.G1({1, 0, 0}), 0);
      EXPECT_EQ(d.lambda({1, 0, 0}), std::numeric_limits<double>::infinity());
      EXPECT_EQ(d.D({1, 0, 0}), 0);
      EXPECT_EQ(d.G2({1, 0, 0}, {0, 0, 1}), 0);
      EXPECT_EQ(d.visibility({0, 0, 1}, {0.6, 0, -0.8}), 0);
    }
  for (const double alpha : {0.0, 1e-3, 0.5, 1.0}) {
    const Gtr1Distribution d(alpha);
    for (const Point2 u : us) {
      const Vec3 m = d.sampleNormal(u);
      ASSERT_TRUE(isFinite(m));
      ASSERT_TRUE(std::isfinite(d.D(m)));
      for (const Vec3 wo : views()) {
        if (const auto wi = d.sampleReflection(wo, u)) {
          ASSERT_TRUE(std::isfinite(d.reflectionPdf(wo, *wi)));
        }
      }
    }
  }
}

TEST(Stability, InvalidParametersAreRejected) {
  DisneyParams p;
  p.roughness = 1.5;
  EXPECT_THROW(DisneyBrdf{p}, std::invalid_argument);
  p.roughness = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(DisneyBrdf{p}, std::invalid_argument);
  p = {};
  p.baseColor = {0.5, -0.1, 0.5};
  try {
    DisneyBrdf{p};
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("baseColor.g"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nuld
