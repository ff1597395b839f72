// Tests of the microfacet helpers (materials/microfacet.h) and the cosine
// hemisphere map: normalization of GGX, its visible normals and GTR1 by
// deterministic quadrature, Smith masking identities, and chi-square tests of
// every sampling routine against its pdf.

#include "materials/microfacet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "materials/sampling.h"
#include "materials/sphere_map.h"
#include "sampler/sequences/rng.h"
#include "tests/materials/chi_square.h"
#include "tests/materials/directions.h"
#include "tests/materials/quadrature.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;

using test::fromAngles;

// Integral over the upper hemisphere of a function of direction, resolving
// a peak at the pole.
double hemisphereIntegral(const std::function<double(Vec3)> &f) {
  const auto cells = test::integrateCells([&](Point2 p) { return 4 * kPi * f(sphereDirection(p)); },
                                          test::uniformEdges(0, 1, 16),
                                          test::uniformEdges(0, 0.5, 8), test::peakAt());
  double sum = 0;
  for (double c : cells) sum += c;
  return sum;
}

struct Alphas {
  double x, y;
};
const std::vector<Alphas> kAlphas = {{1e-4, 1e-4}, {0.02, 0.02}, {0.3, 0.3}, {1, 1},
                                     {0.1, 0.5},   {0.8, 0.15},  {0.01, 0.3}};

TEST(Ggx, AlphaIsClampedToItsFloor) {
  const GgxDistribution d(0, -1);
  EXPECT_EQ(d.alphaX(), GgxDistribution::kMinAlpha);
  EXPECT_EQ(d.alphaY(), GgxDistribution::kMinAlpha);
}

TEST(Ggx, ProjectedAreaOfMicrofacetsIsOne) {
  for (const auto [ax, ay] : kAlphas) {
    const GgxDistribution d(ax, ay);
    const double integral = hemisphereIntegral([&](Vec3 m) { return d.D(m) * m.z; });
    EXPECT_NEAR(integral, 1, 1e-5) << "alpha " << ax << " x " << ay;
  }
}

TEST(Ggx, VisibleNormalsIntegrateToOne) {
  for (const auto [ax, ay] : kAlphas)
    for (const double theta : {0.0, 30.0, 60.0, 85.0, 89.9}) {
      const GgxDistribution d(ax, ay);
      const Vec3 wo = fromAngles(theta, 35);
      const double integral = hemisphereIntegral([&](Vec3 m) { return d.visibleD(wo, m); });
      EXPECT_NEAR(integral, 1, 1e-4) << "alpha " << ax << " x " << ay << ", theta " << theta;
    }
}

TEST(Ggx, SmithMaskingIdentities) {
  Rng rng(11);
  for (const auto [ax, ay] : kAlphas) {
    const GgxDistribution d(ax, ay);
    EXPECT_DOUBLE_EQ(d.G1({0, 0, 1}), 1.0);
    EXPECT_EQ(d.G1({1, 0, 0}), 0.0);
    EXPECT_EQ(d.G1({0.6, 0, -0.8}), 0.0);
    for (int k = 0; k < 2000; ++k) {
      const Vec3 wo = cosineHemisphere({rng.uniform(), rng.uniform()});
      const Vec3 wi = cosineHemisphere({rng.uniform(), rng.uniform()});
      const double g1o = d.G1(wo), g1i = d.G1(wi), g2 = d.G2(wo, wi);
      ASSERT_GE(g1o, 0);
      ASSERT_LE(g1o, 1);
      EXPECT_NEAR(g1o, 1 / (1 + d.lambda(wo)), 1e-12);
      EXPECT_NEAR(g2, 1 / (1 + d.lambda(wo) + d.lambda(wi)), 1e-12);
      // Height correlation: between the separable product and either G1.
      EXPECT_LE(g2, std::min(g1o, g1i) + 1e-15);
      EXPECT_GE(g2, g1o * g1i - 1e-15);
      EXPECT_DOUBLE_EQ(g2, d.G2(wi, wo));
      EXPECT_NEAR(d.visibility(wo, wi), g2 / (4 * wo.z * wi.z), 1e-12 * d.visibility(wo, wi));
    }
  }
}

TEST(Ggx, ReflectionPdfIsVisibleDensityOverJacobian) {
  Rng rng(12);
  const GgxDistribution d(0.2, 0.45);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 wo = cosineHemisphere({rng.uniform(), rng.uniform()});
    const Vec3 wi = cosineHemisphere({rng.uniform(), rng.uniform()});
    const Vec3 h = normalize(wo + wi);
    const double expected = d.visibleD(wo, h) / (4 * dot(wo, h));
    EXPECT_NEAR(d.reflectionPdf(wo, wi), expected, 1e-12 * expected);
  }
  EXPECT_EQ(d.reflectionPdf({0, 0, 1}, {0.6, 0, -0.8}), 0.0);
  EXPECT_EQ(d.reflectionPdf({0.6, 0, -0.8}, {0, 0, 1}), 0.0);
}

// ------------------------------------------------------------ chi-square

void expectPasses(const test::DirectionTest &t, const std::string &name) {
  EXPECT_GT(t.chi.pValue, test::sidakLevel()) << name << ": " << t.describe();
  EXPECT_EQ(t.belowFraction, 0) << name;
  EXPECT_LE(t.pdfMass, 1 + 1e-5) << name;
}

TEST(Ggx, VisibleNormalSamplingMatchesVisibleDensity) {
  struct Case {
    Alphas a;
    double theta, phi;
  };
  const std::vector<Case> cases = {{{0.1, 0.1}, 45, 0},   {{0.5, 0.5}, 0, 0},
                                   {{1, 1}, 80, 10},      {{0.15, 0.6}, 60, 30},
                                   {{0.7, 0.2}, 89, -50}, {{0.3, 0.3}, 89.9, 0}};
  std::uint64_t seed = 100;
  for (const auto &c : cases) {
    const GgxDistribution d(c.a.x, c.a.y);
    const Vec3 wo = fromAngles(c.theta, c.phi);
    const auto t = test::testDirections(
        [&](Point2 u) -> std::optional<Vec3> { return d.sampleVisibleNormal(wo, u); },
        [&](Vec3 m) { return d.visibleD(wo, m); }, 300000, seed++, test::peakAt());
    expectPasses(t, "alpha " + std::to_string(c.a.x) + " x " + std::to_string(c.a.y) + ", theta " +
                        std::to_string(c.theta));
  }
}

TEST(Ggx, ReflectionSamplingMatchesReflectionPdf) {
  for (const auto [ax, ay, theta] :
       std::vector<std::array<double, 3>>{{0.05, 0.05, 30}, {0.4, 0.1, 70}, {1, 1, 85}}) {
    const GgxDistribution d(ax, ay);
    const Vec3 wo = fromAngles(theta, 20);
    const auto t = test::testDirections([&](Point2 u) { return d.sampleReflection(wo, u); },
                                        [&](Vec3 wi) { return d.reflectionPdf(wo, wi); }, 300000,
                                        200 + int(theta), test::peakAt(reflect(wo, {0, 0, 1})));
    expectPasses(t, "reflection alpha " + std::to_string(ax) + ", theta " + std::to_string(theta));
    // The mass below the horizon is exactly what the sampler fails on.
    EXPECT_NEAR(t.failedFraction, 1 - t.pdfMass, 5 * std::sqrt((1 - t.pdfMass) / 300000) + 1e-4);
  }
}

// The test has power: samples of one roughness fail against another's pdf.
TEST(Ggx, ChiSquareRejectsAWrongRoughness) {
  const GgxDistribution sampled(0.3, 0.3), claimed(0.33, 0.33);
  const Vec3 wo = fromAngles(40, 0);
  const auto t = test::testDirections(
      [&](Point2 u) -> std::optional<Vec3> { return sampled.sampleVisibleNormal(wo, u); },
      [&](Vec3 m) { return claimed.visibleD(wo, m); }, 300000, 7, test::peakAt());
  EXPECT_LT(t.chi.pValue, 1e-6) << t.describe();
}

// ------------------------------------------------------------------ GTR1

TEST(Gtr1, ProjectedAreaOfMicrofacetsIsOne) {
  for (const double alpha : {0.001, 0.01, 0.1, 0.5, 0.999, 1.0}) {
    const Gtr1Distribution d(alpha);
    EXPECT_NEAR(hemisphereIntegral([&](Vec3 m) { return d.D(m) * m.z; }), 1, 1e-5)
        << "alpha " << alpha;
  }
}

TEST(Gtr1, NormalSamplingMatchesDensity) {
  std::uint64_t seed = 300;
  for (const double alpha : {0.001, 0.05, 0.3, 1.0}) {
    const Gtr1Distribution d(alpha);
    const auto t =
        test::testDirections([&](Point2 u) -> std::optional<Vec3> { return d.sampleNormal(u); },
                             [&](Vec3 m) { return d.D(m) * m.z; }, 300000, seed++, test::peakAt());
    expectPasses(t, "GTR1 alpha " + std::to_string(alpha));
  }
}

TEST(Gtr1, ReflectionSamplingMatchesReflectionPdf) {
  std::uint64_t seed = 400;
  for (const double theta : {20.0, 75.0}) {
    const Gtr1Distribution d(0.05);
    const Vec3 wo = fromAngles(theta, 0);
    const auto t = test::testDirections([&](Point2 u) { return d.sampleReflection(wo, u); },
                                        [&](Vec3 wi) { return d.reflectionPdf(wo, wi); }, 300000,
                                        seed++, test::peakAt(reflect(wo, {0, 0, 1})));
    expectPasses(t, "GTR1 reflection, theta " + std::to_string(theta));
  }
}

// --------------------------------------------------------- cosine hemisphere

TEST(CosineHemisphere, SamplingMatchesPdfAndNeverHitsTheHorizon) {
  const auto t =
      test::testDirections([](Point2 u) -> std::optional<Vec3> { return cosineHemisphere(u); },
                           [](Vec3 w) { return cosineHemispherePdf(w.z); }, 300000, 500);
  expectPasses(t, "cosine hemisphere");
  EXPECT_NEAR(t.pdfMass, 1, 1e-6);
  EXPECT_EQ(t.failedFraction, 0);
  EXPECT_EQ(cosineHemisphere({0, 0}).z, 1.0);
  const double justBelowOne = std::nextafter(1.0, 0.0);
  EXPECT_GT(cosineHemisphere({justBelowOne, justBelowOne}).z, 0);
}

}  // namespace
}  // namespace nuld
