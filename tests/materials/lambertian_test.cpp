// Tests of the Lambertian BRDF (materials/lambertian.h): values, the white
// furnace, sampling against its pdf, and back-facing directions.

#include "materials/lambertian.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sampler/sequences/rng.h"
#include "tests/materials/chi_square.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Lambertian, ValueIsAlbedoOverPi) {
  const Lambertian l({0.2, 0.5, 0.9});
  EXPECT_EQ(l.name(), "lambertian");
  const Rgb f = l.eval({0, 0.6, 0.8}, {0.6, 0, 0.8});
  EXPECT_DOUBLE_EQ(f.r, 0.2 / kPi);
  EXPECT_DOUBLE_EQ(f.g, 0.5 / kPi);
  EXPECT_DOUBLE_EQ(f.b, 0.9 / kPi);
}

// Albedo 1 reflects everything: estimated with uniform hemisphere directions
// (independent of the BRDF's own sampler) and, sample by sample, with it.
TEST(Lambertian, WhiteFurnace) {
  const Lambertian l(Rgb::grey(1));
  const Vec3 wo = normalize(Vec3{0.3, -0.5, 0.4});
  Rng rng(41);
  constexpr int n = 400000;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < n; ++k) {
    const double z = rng.uniform(), phi = 2 * kPi * rng.uniform();
    const double r = std::sqrt(1 - z * z);
    const Vec3 wi{r * std::cos(phi), r * std::sin(phi), z};
    const double w = l.eval(wo, wi).luminance() * wi.z * 2 * kPi;  // pdf 1 / (2 pi)
    sum += w;
    sum2 += w * w;
  }
  const double mean = sum / n, stdError = std::sqrt((sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, 1, 4 * stdError);
  for (int k = 0; k < 1000; ++k) {
    const auto s = l.sample(wo, 0.5, {rng.uniform(), rng.uniform()});
    ASSERT_TRUE(s);
    EXPECT_NEAR(s->f.luminance() * s->wi.z / s->pdf, 1, 1e-12);
  }
}

TEST(Lambertian, SamplingMatchesPdf) {
  const Lambertian l(Rgb::grey(0.5));
  const Vec3 wo = normalize(Vec3{-0.2, 0.1, 0.3});
  const auto t = test::testDirections(
      [&](Point2 u) -> std::optional<Vec3> {
        const auto s = l.sample(wo, 0.5, u);
        return s ? std::optional<Vec3>(s->wi) : std::nullopt;
      },
      [&](Vec3 wi) { return l.pdf(wo, wi); }, 300000, 42);
  EXPECT_GT(t.chi.pValue, test::sidakLevel()) << t.describe();
  EXPECT_NEAR(t.pdfMass, 1, 1e-6);
  EXPECT_EQ(t.failedFraction, 0);
}

TEST(Lambertian, BackFacingGivesNothing) {
  const Lambertian l(Rgb::grey(1));
  const Vec3 up{0, 0, 1}, down{0, 0.6, -0.8}, horizon{1, 0, 0};
  EXPECT_TRUE(l.eval(up, down).isBlack());
  EXPECT_TRUE(l.eval(down, up).isBlack());
  EXPECT_TRUE(l.eval(horizon, up).isBlack());
  EXPECT_EQ(l.pdf(up, down), 0);
  EXPECT_EQ(l.pdf(down, up), 0);
  EXPECT_FALSE(l.sample(down, 0.5, {0.3, 0.3}));
  EXPECT_FALSE(l.sample(horizon, 0.5, {0.3, 0.3}));
}

}  // namespace
}  // namespace nuld
