// Tests of DisneyBrdf's sampling (materials/disney.h), under every lobe
// choice: chi-square of sample() against pdf() over roughness, anisotropy,
// metallic, subsurface, clearcoat and view angles up to 89 degrees; the mass
// the pdf leaves out equals the fraction of failed samples; sample() agrees
// with eval() and pdf(), and pdf() with evalWithPdf() bit for bit; the
// per-lobe API composes into the mixture exactly as the lobe choice's
// probabilities say.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "materials/disney.h"
#include "materials/disney_target.h"
#include "sampler/sequences/rng.h"
#include "tests/materials/chi_square.h"
#include "tests/materials/directions.h"
#include "tests/materials/disney_cases.h"

namespace nuld {
namespace {

constexpr int kSamples = 400000;
constexpr LobeChoice kChoices[] = {LobeChoice::Uniform, LobeChoice::Weight, LobeChoice::Albedo};

using test::fromAngles;

struct Case {
  std::string name;
  DisneyParams params;
  double theta = 45, phi = 20;
};

std::vector<Case> samplingCases() {
  std::vector<Case> cases;
  // The supplement's instance with roughness x anisotropy varied.
  for (const double r : {0.01, 0.3, 0.58, 1.0})
    for (const double a : {0.0, 0.15, 0.9}) {
      DisneyParams p = supplementDisneyParams();
      p.roughness = r;
      p.anisotropic = a;
      cases.push_back({"roughness " + std::to_string(r) + " anisotropic " + std::to_string(a), p});
    }
  for (const double m : {0.0, 1.0}) {
    DisneyParams p = supplementDisneyParams();
    p.metallic = m;
    cases.push_back({"metallic " + std::to_string(m), p});
  }
  {
    DisneyParams p;  // Burley's defaults, all subsurface
    p.subsurface = 1;
    cases.push_back({"subsurface 1", p});
  }
  {
    DisneyParams p;
    p.baseColor = {0.9, 0.4, 0.1};
    p.roughness = 0.4;
    p.clearcoat = 1;
    p.clearcoatGloss = 1;  // GTR1 alpha 0.001: a very sharp coat
    cases.push_back({"clearcoat glossy", p, 30, 0});
  }
  cases.push_back({"all parameters", test::allParametersNonZero(0.2), 60, 135});
  // Toward grazing view.
  for (const double theta : {0.0, 70.0, 85.0, 89.0})
    cases.push_back(
        {"supplement theta " + std::to_string(theta), supplementDisneyParams(), theta, 0});
  {
    DisneyParams p = supplementDisneyParams();
    p.roughness = 0.01;
    cases.push_back({"roughness 0.01 theta 80", p, 80, -40});
    p.roughness = 0.3;
    p.anisotropic = 0.9;
    cases.push_back({"roughness 0.3 anisotropic 0.9 theta 89", p, 89, 60});
  }
  return cases;
}

// The renderer's form, sample(wo, uc, u), its lobe choice a number of its
// own; `square`: the studies' form, sampleSquare(wo, u).
test::DirectionTest runCase(const DisneyBrdf &brdf, Vec3 wo, std::uint64_t seed,
                            bool square = false) {
  return test::testDirections(
      [&](Point2 u) -> std::optional<Vec3> {
        const auto s = square ? brdf.sampleSquare(wo, u) : brdf.sample(wo, test::choiceOf(u), u);
        return s ? std::optional<Vec3>(s->wi) : std::nullopt;
      },
      [&](Vec3 wi) { return brdf.pdf(wo, wi); }, kSamples, seed,
      test::peakAt(reflect(wo, Vec3{0, 0, 1})));
}

// One lobe choice's cases (a test per choice, so that ctest runs them side
// by side).
void chiSquareAgainstPdf(LobeChoice choice, std::uint64_t seed, bool square = false) {
  double minP = 1;
  for (const Case &c : samplingCases()) {
    const DisneyBrdf brdf(c.params, choice);
    const Vec3 wo = fromAngles(c.theta, c.phi);
    const auto t = runCase(brdf, wo, seed++, square);
    minP = std::min(minP, t.chi.pValue);
    EXPECT_GT(t.chi.pValue, test::sidakLevel()) << c.name << ": " << t.describe();
    EXPECT_EQ(t.belowFraction, 0) << c.name;
    // The pdf integrates to at most 1; what is missing is exactly the
    // samples that fail (specular reflections below the horizon).
    EXPECT_LE(t.pdfMass, 1 + 1e-5) << c.name;
    const double missing = std::max(0.0, 1 - t.pdfMass);
    EXPECT_NEAR(t.failedFraction, missing, 5 * std::sqrt(missing / kSamples) + 2e-5)
        << c.name << ": " << t.describe();
  }
  std::cout << "[ info ] smallest chi-square p-value over Disney cases (" << toString(choice)
            << "): " << minP << "\n";
}

TEST(DisneySampling, ChiSquareAgainstPdfUniformChoice) {
  chiSquareAgainstPdf(LobeChoice::Uniform, 1000);
}
TEST(DisneySampling, ChiSquareAgainstPdfWeightChoice) {
  chiSquareAgainstPdf(LobeChoice::Weight, 2000);
}
TEST(DisneySampling, ChiSquareAgainstPdfAlbedoChoice) {
  chiSquareAgainstPdf(LobeChoice::Albedo, 3000);
}
// The square's form (u.x chooses the lobe, rescaled), which the studies of
// 2D sets on a BSDF integrand use.
TEST(DisneySampling, ChiSquareAgainstPdfSquareForm) {
  chiSquareAgainstPdf(LobeChoice::Albedo, 4000, true);
}

// The test has power: sampling one roughness while claiming another fails,
// and so does a sampler that silently drops 1 % of its samples (its shape is
// unchanged; only the failure bin sees it).
TEST(DisneySampling, ChiSquareRejectsWrongPdfAndDroppedSamples) {
  DisneyParams p = supplementDisneyParams();
  const DisneyBrdf sampled(p);
  p.roughness = 0.5;
  const DisneyBrdf claimed(p);
  const Vec3 wo = supplementWo();
  const auto wrong = test::testDirections(
      [&](Point2 u) -> std::optional<Vec3> {
        const auto s = sampled.sampleSquare(wo, u);
        return s ? std::optional<Vec3>(s->wi) : std::nullopt;
      },
      [&](Vec3 wi) { return claimed.pdf(wo, wi); }, kSamples, 5);
  EXPECT_LT(wrong.chi.pValue, 1e-6) << wrong.describe();

  const auto dropped = test::testDirections(
      [&](Point2 u) -> std::optional<Vec3> {
        // Drop on a hash of u, independent of the direction produced.
        if (mix64(std::uint64_t(u.x * 0x1p53) ^ std::uint64_t(u.y * 0x1p52)) % 100 == 0)
          return std::nullopt;
        const auto s = sampled.sampleSquare(wo, u);
        return s ? std::optional<Vec3>(s->wi) : std::nullopt;
      },
      [&](Vec3 wi) { return sampled.pdf(wo, wi); }, kSamples, 6);
  EXPECT_LT(dropped.chi.pValue, 1e-6) << dropped.describe();
}

TEST(DisneySampling, SampleReturnsFullEvalAndMixturePdf) {
  Rng rng(21);
  for (const LobeChoice choice : kChoices)
    for (const Case &c : samplingCases()) {
      const DisneyBrdf brdf(c.params, choice);
      const Vec3 wo = fromAngles(c.theta, c.phi);
      for (int k = 0; k < 2000; ++k) {
        const auto s = brdf.sampleSquare(wo, {rng.uniform(), rng.uniform()});
        if (!s) continue;
        ASSERT_GT(s->pdf, 0) << c.name;
        EXPECT_NEAR(std::sqrt(lengthSquared(s->wi)), 1, 1e-12);
        EXPECT_EQ(s->pdf, brdf.pdf(wo, s->wi)) << c.name << " " << toString(choice);
        EXPECT_EQ(s->f, brdf.eval(wo, s->wi)) << c.name << " " << toString(choice);
      }
      // pdf() and evalWithPdf() agree bit for bit at any direction,
      // below the surface included.
      for (int k = 0; k < 200; ++k) {
        const Vec3 wi = k % 10 == 0 ? Vec3{0.6, 0, -0.8} : test::randomUpper(rng);
        EXPECT_EQ(brdf.evalWithPdf(wo, wi).pdf, brdf.pdf(wo, wi))
            << c.name << " " << toString(choice);
      }
    }
}

TEST(DisneySampling, LobeApiComposesIntoTheMixture) {
  Rng rng(22);
  for (const LobeChoice choice : kChoices)
    for (const Case &c : samplingCases()) {
      const DisneyBrdf brdf(c.params, choice);
      const std::string name = c.name + " (" + toString(choice) + ")";
      EXPECT_EQ(brdf.lobeCount(), c.params.clearcoat > 0 ? 4 : 3) << name;
      EXPECT_EQ(brdf.params(), c.params);
      EXPECT_EQ(brdf.lobeChoice(), choice);
      const Vec3 wo = fromAngles(c.theta, c.phi);
      const DisneyBrdf::LobeProbabilities p = brdf.lobeProbabilities(wo);
      for (int n = 0; n < 500; ++n) {
        const Vec3 wi = test::randomUpper(rng);
        Rgb f;
        double pdf = 0;
        for (int k = 0; k < brdf.lobeCount(); ++k) {
          f += brdf.evalLobe(k, wo, wi);
          pdf += p[k] * brdf.lobePdf(k, wo, wi);
        }
        const Rgb e = brdf.eval(wo, wi);
        EXPECT_NEAR(f.r, e.r, 1e-12 * (1 + e.r)) << name;
        EXPECT_NEAR(f.b, e.b, 1e-12 * (1 + e.b)) << name;
        EXPECT_NEAR(pdf, brdf.pdf(wo, wi), 1e-12 * (1 + pdf)) << name;
      }
      // sample() is sampleLobe(k) with u.x = start_k + u' p_k, start_k the
      // sum of the probabilities before k.
      for (int n = 0; n < 500; ++n) {
        const int k = int(rng.uniformInt(brdf.lobeCount()));
        if (!(p[k] > 0)) continue;
        double start = 0;
        for (int j = 0; j < k; ++j) start += p[j];
        const double u0 = 0.001 + 0.998 * rng.uniform(), u1 = rng.uniform();
        const auto lobeDir = brdf.sampleLobe(k, wo, {u0, u1});
        const auto s = brdf.sampleSquare(wo, {start + u0 * p[k], u1});
        ASSERT_EQ(lobeDir.has_value(), s.has_value()) << name << " lobe " << k;
        if (!s) continue;
        EXPECT_NEAR(lobeDir->x, s->wi.x, 1e-6) << name;
        EXPECT_NEAR(lobeDir->y, s->wi.y, 1e-6) << name;
        EXPECT_NEAR(lobeDir->z, s->wi.z, 1e-6) << name;
      }
    }
  const DisneyBrdf brdf(supplementDisneyParams());
  EXPECT_EQ(toString(brdf.lobe(0)), "diffuse");
  EXPECT_EQ(toString(brdf.lobe(1)), "subsurface");
  EXPECT_EQ(toString(brdf.lobe(2)), "specular");
  EXPECT_EQ(brdf.lobePdf(3, supplementWo(), {0, 0, 1}), 0);  // no clearcoat lobe here
  EXPECT_FALSE(brdf.sampleLobe(-1, supplementWo(), {0.5, 0.5}));
}

TEST(DisneySampling, LobeChoiceEdgesStayInRange) {
  const DisneyBrdf brdf(supplementDisneyParams());
  const Vec3 wo = supplementWo();
  const double justBelowOne = std::nextafter(1.0, 0.0);
  for (const double ux : {0.0, 1.0 / 3, 2.0 / 3, justBelowOne, 1.0})
    for (const double uy : {0.0, 0.5, justBelowOne}) {
      const auto s = brdf.sampleSquare(wo, {ux, uy});
      if (!s) continue;
      EXPECT_GT(s->wi.z, 0);
      EXPECT_TRUE(s->f.isFinite());
      EXPECT_GT(s->pdf, 0);
    }
  // The diffuse lobe never fails: u = (0, 0) is the normal.
  const auto first = brdf.sampleSquare(wo, {0, 0});
  ASSERT_TRUE(first);
  EXPECT_EQ(first->wi.z, 1.0);
}

}  // namespace
}  // namespace nuld

namespace nuld {
namespace {

// The lobe choices' probabilities: a distribution over the lobes (none
// beyond lobeCount), positive for every lobe that is a term of f under
// every choice, uniform as the supplement's, Mitsuba's static weights for
// `weight`, and for `albedo` a function of the view's cos theta alone (so
// a table's symmetries keep it) that favours the specular lobe at grazing
// views.
TEST(DisneySampling, LobeChoiceProbabilities) {
  const std::vector<DisneyParams> materials = [] {
    std::vector<DisneyParams> out{supplementDisneyParams(), test::allParametersNonZero(0.3)};
    DisneyParams metal;
    metal.metallic = 1;
    out.push_back(metal);
    DisneyParams black;  // nothing for the albedo estimate but grazing Fresnel
    black.baseColor = {0, 0, 0};
    black.specular = 0;
    out.push_back(black);
    return out;
  }();
  for (const LobeChoice choice : kChoices)
    for (const DisneyParams &params : materials) {
      const DisneyBrdf brdf(params, choice);
      for (const double theta : {0.0, 30.0, 60.0, 85.0, 89.9}) {
        const DisneyBrdf::LobeProbabilities p = brdf.lobeProbabilities(fromAngles(theta, 10));
        EXPECT_EQ(p, brdf.lobeProbabilities(fromAngles(theta, 250))) << toString(choice);
        double sum = 0;
        for (int k = 0; k < 4; ++k) {
          EXPECT_GE(p[k], 0);
          if (k >= brdf.lobeCount()) {
            EXPECT_EQ(p[k], 0);
          }
          sum += p[k];
        }
        EXPECT_NEAR(sum, 1, 1e-12) << toString(choice);
        EXPECT_GT(p[2], 0) << toString(choice);  // the specular lobe is a term of every f
        if (params.metallic < 1) {
          EXPECT_GT(p[0] + p[1], 0) << toString(choice);
        }
        if (params.clearcoat > 0) {
          EXPECT_GT(p[3], 0) << toString(choice);
        }
        if (choice == LobeChoice::Uniform) {
          for (int k = 0; k < brdf.lobeCount(); ++k) EXPECT_EQ(p[k], 1.0 / brdf.lobeCount());
        }
      }
    }
  const Vec3 wo = supplementWo();
  DisneyParams plastic;  // Mitsuba: diffuse 1 - metallic, specular 1
  plastic.roughness = 0.4;
  const auto weight = DisneyBrdf(plastic, LobeChoice::Weight).lobeProbabilities(wo);
  EXPECT_DOUBLE_EQ(weight[0], 0.5);
  EXPECT_EQ(weight[1], 0);
  EXPECT_DOUBLE_EQ(weight[2], 0.5);
  DisneyParams metal;
  metal.metallic = 1;
  metal.clearcoat = 1;
  const auto metalWeight = DisneyBrdf(metal, LobeChoice::Weight).lobeProbabilities(wo);
  EXPECT_EQ(metalWeight[0] + metalWeight[1], 0);
  EXPECT_DOUBLE_EQ(metalWeight[3], 0.25 / 1.25);
  // Albedo: a metal without coat samples its specular lobe only; a white
  // plastic mostly its diffuse lobe near the normal, and more of its
  // specular lobe toward grazing, where Fresnel rises.
  metal.clearcoat = 0;
  EXPECT_EQ(DisneyBrdf(metal, LobeChoice::Albedo).lobeProbabilities(wo)[2], 1);
  const DisneyBrdf albedo(plastic, LobeChoice::Albedo);
  const double normal = albedo.lobeProbabilities(fromAngles(0, 0))[2],
               grazing = albedo.lobeProbabilities(fromAngles(85, 0))[2];
  EXPECT_LT(normal, 0.2);
  EXPECT_GT(grazing, 2 * normal);
}

}  // namespace
}  // namespace nuld
