// Tests of DisneyBrdf's values (materials/disney.h): reciprocity, the lobes
// against an independent transcription of Burley's 2012 formulas, and the
// directional albedo (white furnace) of every lobe and of the whole model.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "materials/disney.h"
#include "materials/disney_target.h"
#include "materials/sampling.h"
#include "sampler/sequences/rng.h"
#include "tests/materials/directions.h"
#include "tests/materials/disney_cases.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;

using test::fromAngles;
using test::randomUpper;

TEST(DisneyValues, Reciprocity) {
  Rng rng(31);
  const std::vector<DisneyParams> sets = {supplementDisneyParams(), DisneyParams{},
                                          test::allParametersNonZero(0.35),
                                          test::allParametersNonZero(0.0)};
  for (const DisneyParams &p : sets) {
    const DisneyBrdf brdf(p);
    for (int k = 0; k < 20000; ++k) {
      const Vec3 a = randomUpper(rng), b = randomUpper(rng);
      const Rgb fab = brdf.eval(a, b), fba = brdf.eval(b, a);
      ASSERT_NEAR(fab.r, fba.r, 1e-10 * (1 + fab.r));
      ASSERT_NEAR(fab.g, fba.g, 1e-10 * (1 + fab.g));
      ASSERT_NEAR(fab.b, fba.b, 1e-10 * (1 + fab.b));
    }
  }
}

// evalWithPdf shares the half vector and D between f and pdf; it must give
// eval's and pdf's values bit for bit, above, at and below the horizon, for
// every lobe mix (clearcoat on and off, roughness 0 and 1).
TEST(DisneyValues, EvalWithPdfEqualsEvalAndPdfExactly) {
  Rng rng(37);
  const std::vector<DisneyParams> sets = {
      supplementDisneyParams(), DisneyParams{}, test::allParametersNonZero(0.35),
      test::allParametersNonZero(0.0), test::allParametersNonZero(1.0)};
  const auto check = [](const DisneyBrdf &brdf, Vec3 wo, Vec3 wi) {
    const BsdfValue v = brdf.evalWithPdf(wo, wi);
    const Rgb f = brdf.eval(wo, wi);
    ASSERT_EQ(v.pdf, brdf.pdf(wo, wi))
        << wo.x << "," << wo.y << "," << wo.z << " " << wi.x << "," << wi.y << "," << wi.z;
    ASSERT_TRUE(v.f.r == f.r && v.f.g == f.g && v.f.b == f.b)
        << wo.x << "," << wo.y << "," << wo.z << " " << wi.x << "," << wi.y << "," << wi.z;
  };
  for (const DisneyParams &p : sets) {
    const DisneyBrdf brdf(p);
    for (int k = 0; k < 5000; ++k) {
      Vec3 wo = randomUpper(rng), wi = randomUpper(rng);
      check(brdf, wo, wi);
      check(brdf, wo, reflect(wo, {0, 0, 1}));  // the mirror direction
      wi.z = -wi.z;
      check(brdf, wo, wi);  // below the surface: f = 0, pdf = 0
    }
    check(brdf, fromAngles(90, 0), fromAngles(89.999, 180));
    check(brdf, {0, 0, 1}, {0, 0, 1});
  }
}

// Burley's formulas written out a second time, from his notes, in the
// textbook form (tangents, separate G1 factors) rather than the cancelled one.
Rgb burleyReference(const DisneyParams &p, Vec3 v, Vec3 l) {
  const Vec3 h = normalize(v + l);
  const double nl = l.z, nv = v.z, lh = dot(l, h);
  const auto schlick = [](double c) { return std::pow(1 - c, 5); };
  const auto mix = [](double t, auto a, auto b) { return (1 - t) * a + t * b; };
  const Rgb base = p.baseColor;
  const Rgb tint = base / base.luminance();
  const Rgb spec0 =
      mix(p.metallic, p.specular * 0.08 * mix(p.specularTint, Rgb::grey(1), tint), base);
  const Rgb sheenColor = mix(p.sheenTint, Rgb::grey(1), tint);
  const double fl = schlick(nl), fv = schlick(nv), fh = schlick(lh);
  const double fd90 = 0.5 + 2 * lh * lh * p.roughness;
  const double fd = mix(fl, 1.0, fd90) * mix(fv, 1.0, fd90);
  const double fss90 = lh * lh * p.roughness;
  const double fss = mix(fl, 1.0, fss90) * mix(fv, 1.0, fss90);
  const double ss = 1.25 * (fss * (1 / (nl + nv) - 0.5) + 0.5);
  const Rgb diffuse =
      (1 - p.metallic) * (mix(p.subsurface, fd, ss) / kPi * base + fh * p.sheen * sheenColor);

  const double aspect = std::sqrt(1 - 0.9 * p.anisotropic);
  const double ax = std::max(1e-4, p.roughness * p.roughness / aspect);
  const double ay = std::max(1e-4, p.roughness * p.roughness * aspect);
  const double cos2 = h.z * h.z, tan2 = (1 - cos2) / cos2;
  const double cosPhi2 = h.x * h.x / (h.x * h.x + h.y * h.y), sinPhi2 = 1 - cosPhi2;
  const double ds = 1 / (kPi * ax * ay * cos2 * cos2 *
                         std::pow(1 + tan2 * (cosPhi2 / (ax * ax) + sinPhi2 / (ay * ay)), 2));
  const auto lambda = [&](Vec3 w) {
    const double t2 = (1 - w.z * w.z) / (w.z * w.z);
    const double c2 = w.x * w.x / (w.x * w.x + w.y * w.y);
    const double a2 = c2 * ax * ax + (1 - c2) * ay * ay;
    return (-1 + std::sqrt(1 + a2 * t2)) / 2;
  };
  const double g2 = 1 / (1 + lambda(v) + lambda(l));
  const Rgb specular = ds * g2 / (4 * nl * nv) * mix(fh, spec0, Rgb::grey(1));

  Rgb coat;
  if (p.clearcoat > 0) {
    const double a = mix(p.clearcoatGloss, 0.1, 0.001), a2 = a * a;
    const double dr = (a2 - 1) / (kPi * std::log(a2) * (1 + (a2 - 1) * cos2));
    const auto lambdaCoat = [](Vec3 w) {
      const double t2 = (1 - w.z * w.z) / (w.z * w.z);
      return (-1 + std::sqrt(1 + 0.0625 * t2)) / 2;
    };
    const double gr = 1 / (1 + lambdaCoat(v) + lambdaCoat(l));
    coat = Rgb::grey(0.25 * p.clearcoat * mix(fh, 0.04, 1.0) * dr * gr / (4 * nl * nv));
  }
  return diffuse + specular + coat;
}

TEST(DisneyValues, MatchesAnIndependentTranscriptionOfBurley) {
  Rng rng(32);
  std::vector<DisneyParams> sets = {supplementDisneyParams(), DisneyParams{},
                                    test::allParametersNonZero(0.35)};
  for (DisneyParams p : sets) {
    const DisneyBrdf brdf(p);
    for (int k = 0; k < 5000; ++k) {
      const Vec3 v = randomUpper(rng), l = randomUpper(rng);
      const Rgb f = brdf.eval(v, l), ref = burleyReference(p, v, l);
      ASSERT_NEAR(f.r, ref.r, 1e-9 * (1 + ref.r));
      ASSERT_NEAR(f.g, ref.g, 1e-9 * (1 + ref.g));
      ASSERT_NEAR(f.b, ref.b, 1e-9 * (1 + ref.b));
    }
  }
}

// ------------------------------------------------------------------ albedo

struct Estimate {
  double mean = 0, stdError = 0;
};

// The directional albedo: integral of luminance(f) cos over wi, by
// importance sampling with the BRDF's own sampler (validated by the
// chi-square tests).
Estimate albedo(const DisneyBrdf &brdf, Vec3 wo, int n, std::uint64_t seed) {
  Rng rng(seed);
  double sum = 0, sum2 = 0;
  for (int k = 0; k < n; ++k) {
    const auto s = brdf.sampleSquare(wo, {rng.uniform(), rng.uniform()});
    const double w = s ? s->f.luminance() * s->wi.z / s->pdf : 0;
    sum += w;
    sum2 += w * w;
  }
  const double mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

// A white GGX lobe cannot create energy: with wi drawn from the visible
// normals, f cos / pdf = F G2 / G1(wo) <= 1 sample by sample (F <= 1 and the
// height-correlated G2 <= G1(wo)), so its albedo is at most 1 for every
// roughness, anisotropy and view angle.
TEST(DisneyValues, SpecularLobeWeightNeverExceedsOne) {
  Rng rng(33);
  for (const double r : {0.0, 0.05, 0.3, 0.7, 1.0})
    for (const double a : {0.0, 0.9})
      for (const double theta : {0.0, 45.0, 80.0, 89.9}) {
        DisneyParams p;
        p.metallic = 1;
        p.roughness = r;
        p.anisotropic = a;
        const DisneyBrdf brdf(p);
        const int spec = int(DisneyLobe::Specular);
        const Vec3 wo = fromAngles(theta, 30);
        for (int k = 0; k < 2000; ++k) {
          const auto wi = brdf.sampleLobe(spec, wo, {rng.uniform(), rng.uniform()});
          if (!wi) continue;
          const double w =
              brdf.evalLobe(spec, wo, *wi).luminance() * wi->z / brdf.lobePdf(spec, wo, *wi);
          ASSERT_LE(w, 1 + 1e-9) << "roughness " << r << " theta " << theta;
        }
      }
}

// At normal view (F_V = 0) the diffuse lobe's albedo has a closed form:
// 1 + integral of (fd90 - 1) (1 - mu)^5 2 mu dmu with fd90 = 0.5 + r (1 + mu)
// (cos^2 theta_d = (1 + mu) / 2), i.e. 1 + (10 r - 4) / 168.
TEST(DisneyValues, DiffuseAlbedoAtNormalViewMatchesClosedForm) {
  Rng rng(34);
  for (const double r : {0.0, 0.3, 0.58, 1.0}) {
    DisneyParams p;
    p.roughness = r;
    const DisneyBrdf brdf(p);
    constexpr int n = 200000;
    double sum = 0;
    for (int k = 0; k < n; ++k) {
      const Vec3 wi = cosineHemisphere({rng.uniform(), rng.uniform()});
      sum += brdf.evalLobe(int(DisneyLobe::Diffuse), {0, 0, 1}, wi).luminance() * kPi;
    }
    // The weight stays within [0.97, 1.1]: sigma < 1e-4 at this n.
    EXPECT_NEAR(sum / n, 1 + (10 * r - 4) / 168, 5e-4) << "roughness " << r;
  }
}

// Burley's model does not conserve energy, and the tests hold it to what it
// is rather than to 1: the diffuse lobe is not reduced by the specular
// Fresnel, retro-reflection raises fd90 up to 2.5 at grazing angles, sheen is
// added on top, and the subsurface term's 1 / (cos + cos) grows at grazing
// view. Measured over a wider sweep (white base, subsurface, sheen and
// specular each 0 / 0.5 / 1, 20k samples each) the albedo peaks at
// 1.80 +- 0.003 (subsurface 1, sheen 1, specular 1, roughness 0.1, view 85
// degrees); the diffuse lobe alone reaches 1.60 (roughness 1, view 89.9), and
// Burley's defaults give 1.04 at normal view, 1.23 at 89.9 degrees.
// What the test asserts: a pure metal (metallic 1, the lobe bounded above)
// stays <= 1 within Monte Carlo error; every configuration stays below 1.85,
// a regression bound 10 standard errors above the measured peak.
TEST(DisneyValues, WhiteFurnaceAlbedoBounds) {
  double maxAlbedo = 0;
  std::string argmax;
  std::uint64_t seed = 4000;
  for (const double r : {0.0, 0.1, 0.5, 1.0})
    for (const double m : {0.0, 0.5, 1.0})
      for (const double a : {0.0, 0.9})
        for (const double extras : {0.0, 1.0})  // subsurface, sheen, specular all 0 or all 1
          for (const double theta : {0.0, 45.0, 85.0, 89.9}) {
            DisneyParams p;
            p.roughness = r;
            p.metallic = m;
            p.anisotropic = a;
            p.subsurface = p.sheen = p.specular = extras;
            const DisneyBrdf brdf(p);
            const Estimate e = albedo(brdf, fromAngles(theta, 30), 8000, seed++);
            const std::string name = "roughness " + std::to_string(r) + " metallic " +
                                     std::to_string(m) + " anisotropic " + std::to_string(a) +
                                     " extras " + std::to_string(extras) + " theta " +
                                     std::to_string(theta);
            if (m == 1) {
              EXPECT_LE(e.mean, 1 + 4 * e.stdError) << name;
            }
            EXPECT_LE(e.mean, 1.85) << name;
            // Not black: even the roughest anisotropic metal (alpha_x = 2.3)
            // keeps about 18 % after masking.
            EXPECT_GT(e.mean, 0.1) << name;
            if (e.mean > maxAlbedo) {
              maxAlbedo = e.mean;
              argmax = name;
            }
          }
  std::cout << "[ info ] largest white-furnace albedo " << maxAlbedo << " at " << argmax << "\n";
}

}  // namespace
}  // namespace nuld
