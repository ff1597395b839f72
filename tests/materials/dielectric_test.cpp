// The transmitting Disney lobe (materials/dielectric.h) against closed forms:
// the Fresnel equations in their trigonometric form, a smooth slab's
// reflectance and transmittance with its interreflections, a white furnace
// for the rough interface, chi-square tests of reflection and refraction
// sampling over the whole sphere, and finite values at the stiff cases.

#include "materials/dielectric.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>

#include "materials/disney.h"
#include "materials/sphere_map.h"
#include "sampler/sequences/rng.h"
#include "tests/materials/chi_square.h"
#include "tests/materials/directions.h"

namespace nuld {
namespace {

using test::fromAngles;
constexpr double kDeg = std::numbers::pi / 180;

DisneyParams glass(double roughness, double ior) {
  DisneyParams p;
  p.specTrans = 1;
  p.roughness = roughness;
  p.ior = ior;
  return p;
}

// Fresnel's equations through the refraction angle (sines and tangents), an
// independent form of the cosine form the code uses.
double fresnelTrig(double thetaI, double eta) {
  if (thetaI == 0) return std::pow((eta - 1) / (eta + 1), 2);
  const double sinT = std::sin(thetaI) / eta;
  if (sinT >= 1) return 1;
  const double thetaT = std::asin(sinT);
  const double rs = std::sin(thetaI - thetaT) / std::sin(thetaI + thetaT);
  const double rp = std::tan(thetaI - thetaT) / std::tan(thetaI + thetaT);
  return 0.5 * (rs * rs + rp * rp);
}

TEST(Dielectric, FresnelMatchesTheTrigonometricForm) {
  for (const double eta : {1.0001, 1.25, 1.5, 2.5, 1 / 1.5, 1 / 2.5})
    for (const double deg : {0.0, 10.0, 30.0, 41.0, 45.0, 60.0, 80.0, 89.0}) {
      const double t = deg * kDeg;
      EXPECT_NEAR(fresnelDielectric(std::cos(t), eta), fresnelTrig(t, eta), 1e-12)
          << "eta " << eta << " theta " << deg;
    }
  // Total internal reflection beyond the critical angle, and grazing light.
  const double critical = std::asin(1 / 1.5);
  EXPECT_EQ(fresnelDielectric(std::cos(critical + 1e-6), 1 / 1.5), 1);
  EXPECT_LT(fresnelDielectric(std::cos(critical - 1e-3), 1 / 1.5), 1);
  EXPECT_NEAR(fresnelDielectric(0, 1.5), 1, 1e-12);
  // Brewster's angle: the p-polarized half vanishes, leaving rs^2 / 2.
  const double brewster = std::atan(1.5), thetaT = std::asin(std::sin(brewster) / 1.5);
  EXPECT_NEAR(fresnelDielectric(std::cos(brewster), 1.5),
              0.5 * std::pow(std::sin(brewster - thetaT) / std::sin(brewster + thetaT), 2), 1e-12);
  // Reciprocity of the interface: the same F from either side.
  for (const double deg : {0.0, 20.0, 40.0}) {
    const double t = deg * kDeg, tt = std::asin(std::sin(t) / 1.5);
    EXPECT_NEAR(fresnelDielectric(std::cos(t), 1.5), fresnelDielectric(std::cos(tt), 1 / 1.5),
                1e-12);
  }
}

TEST(Dielectric, RefractionObeysSnell) {
  for (const double eta : {1.25, 1 / 1.25})
    for (const double deg : {0.0, 20.0, 50.0}) {
      const Vec3 w = fromAngles(deg, 30);
      const auto t = refract(w, {0, 0, 1}, eta);
      ASSERT_TRUE(t) << deg;
      EXPECT_NEAR(std::sqrt(1 - t->z * t->z) * eta, std::sqrt(1 - w.z * w.z), 1e-12);
      EXPECT_LT(t->z, 0);
      EXPECT_NEAR(length(*t), 1, 1e-12);
    }
  EXPECT_FALSE(refract(fromAngles(60, 0), {0, 0, 1}, 1 / 1.5));  // beyond 41.8 degrees
}

// A slab of smooth glass between two planes, traced through the material
// alone: the top interface's frame is the world's, the bottom's points down
// (outside is below it). Returns the reflected and transmitted fractions of
// paths weighted by their throughput, and the largest deviation of any
// path's weight from 1 (each smooth choice is made with its Fresnel
// probability, and the 1 / eta^2 of entering cancels the eta^2 of leaving).
struct Slab {
  double reflected = 0, transmitted = 0, worstWeight = 0;
};
Slab traceSlab(const DisneyBrdf &m, double thetaDeg, int paths, std::uint64_t seed) {
  Rng rng(seed);
  Slab out;
  for (int k = 0; k < paths; ++k) {
    Vec3 wo = fromAngles(thetaDeg, 20);  // toward the viewer, in the top frame
    bool top = true;                     // which interface the path is at
    double weight = 1;
    for (int bounce = 0; bounce < 200; ++bounce) {
      const auto s = m.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()});
      if (!s) {
        ADD_FAILURE() << "no sample at bounce " << bounce;
        return out;
      }
      EXPECT_TRUE(s->delta);
      weight *= s->f.g * std::abs(s->wi.z) / s->pdf;
      if (s->wi.z > 0) {  // out of the slab, above the top or below the bottom
        (top ? out.reflected : out.transmitted) += weight / paths;
        out.worstWeight = std::max(out.worstWeight, std::abs(weight - 1));
        break;
      }
      // Into the slab: to the other interface, whose frame is the mirror
      // image; the path arrives there from inside with wo = -wi mirrored.
      wo = {-s->wi.x, -s->wi.y, s->wi.z};
      top = !top;
    }
  }
  return out;
}

TEST(Dielectric, SmoothSlabMatchesFresnelWithInterreflections) {
  constexpr int kPaths = 40000;
  std::uint64_t seed = 11;
  for (const double ior : {1.25, 1.5, 2.5})
    for (const double theta : {0.0, 30.0, 60.0, 85.0}) {
      const DisneyBrdf m(glass(0, ior));
      ASSERT_TRUE(m.onlyDelta());
      // Both interfaces reflect R (the inside angle has the same Fresnel),
      // so the slab reflects R + (1 - R)^2 R / (1 - R^2) = 2R / (1 + R).
      const double r = fresnelDielectric(std::cos(theta * kDeg), ior);
      const double slabR = 2 * r / (1 + r), slabT = (1 - r) / (1 + r);
      const Slab s = traceSlab(m, theta, kPaths, seed++);
      const double se = std::sqrt(slabR * slabT / kPaths);
      EXPECT_NEAR(s.reflected, slabR, 4 * se + 1e-12) << "ior " << ior << " theta " << theta;
      EXPECT_NEAR(s.transmitted, slabT, 4 * se + 1e-12) << "ior " << ior << " theta " << theta;
      EXPECT_LT(s.worstWeight, 1e-12) << "ior " << ior << " theta " << theta;
    }
}

// The rough interface's albedo from wo, in the convention of energy (a
// refracted sample's 1 / eta^2 undone), by its own sampling and, as an
// independent check of eval against sample, by uniform directions over the
// sphere. Also the albedo of a perfect (F = 1) GGX mirror of the same alpha,
// whose loss is the single-scattering loss of GGX.
struct Albedo {
  double sampled = 0, sampledSe = 0, uniform = 0, uniformSe = 0, mirror = 0;
};
Albedo albedo(const DisneyBrdf &m, Vec3 wo, int n, std::uint64_t seed) {
  Rng rng(seed);
  const double eta = wo.z > 0 ? m.params().ior : 1 / m.params().ior;
  double s1 = 0, s2 = 0, u1 = 0, u2 = 0;
  for (int k = 0; k < n; ++k) {
    const Point2 u{rng.uniform(), rng.uniform()};
    double w = 0;
    if (const auto s = m.sample(wo, rng.uniform(), u)) {
      w = s->f.g * std::abs(s->wi.z) / s->pdf;
      if (s->wi.z * wo.z < 0) w *= eta * eta;
    }
    s1 += w, s2 += w * w;
    const Vec3 wi = sphereDirection({rng.uniform(), rng.uniform()});
    double v = m.eval(wo, wi).g * std::abs(wi.z) * 4 * std::numbers::pi;
    if (wi.z * wo.z < 0) v *= eta * eta;
    u1 += v, u2 += v * v;
  }
  Albedo a;
  a.sampled = s1 / n;
  a.sampledSe = std::sqrt(std::max(0.0, s2 / n - a.sampled * a.sampled) / n);
  a.uniform = u1 / n;
  a.uniformSe = std::sqrt(std::max(0.0, u2 / n - a.uniform * a.uniform) / n);
  // The mirror: E[G2 / G1] over visible normals.
  const double alpha =
      std::max(GgxDistribution::kMinAlpha, m.params().roughness * m.params().roughness);
  const GgxDistribution d(alpha, alpha);
  const Vec3 up{wo.x, wo.y, std::abs(wo.z)};
  double e = 0;
  for (int k = 0; k < n; ++k) {
    const Vec3 h = d.sampleVisibleNormal(up, {rng.uniform(), rng.uniform()});
    const Vec3 wi = reflect(up, h);
    if (wi.z > 0) e += d.G2(up, wi) / d.G1(up);
  }
  a.mirror = e / n;
  return a;
}

TEST(Dielectric, RoughInterfaceGainsNoEnergyAndLosesNoMoreThanGgx) {
  constexpr int kN = 200000;
  std::uint64_t seed = 101;
  for (const double roughness : {0.2, 0.5, 1.0})
    for (const double ior : {1.25, 1.5, 2.5})
      for (const double theta : {0.0, 45.0, 80.0, 135.0, 170.0}) {
        const DisneyBrdf m(glass(roughness, ior));
        const Vec3 wo = fromAngles(theta, 30);
        const Albedo a = albedo(m, wo, kN, seed++);
        const std::string name = "roughness " + std::to_string(roughness) + " ior " +
                                 std::to_string(ior) + " theta " + std::to_string(theta);
        EXPECT_LE(a.sampled, 1 + 4 * a.sampledSe) << name;
        EXPECT_NEAR(a.sampled, a.uniform, 4 * std::hypot(a.sampledSe, a.uniformSe)) << name;
        // Seen from outside, what leaves is at least what a perfect GGX
        // mirror keeps (its single-scattering loss bounds the interface's):
        // refracted directions lie nearer the normal than reflected ones, so
        // they are masked less. From inside the refracted directions are
        // the grazing ones, and the bound does not hold (measured: 0.867
        // against 0.886 at roughness 0.5, ior 1.5, 135 degrees).
        if (wo.z > 0) EXPECT_GE(a.sampled, a.mirror - 4 * a.sampledSe) << name;
        std::cout << "[ info ] " << name << ": albedo " << a.sampled << " +- " << a.sampledSe
                  << " (uniform " << a.uniform << "), GGX mirror " << a.mirror << "\n";
      }
}

// Reflection and refraction sampling against the pdf over the whole sphere,
// from outside and from inside, for glass and for a blend with the diffuse.
TEST(Dielectric, ChiSquareAgainstPdfOverTheSphere) {
  struct Case {
    const char *name;
    DisneyParams p;
    double theta;
  };
  DisneyParams blend = glass(0.4, 1.5);
  blend.specTrans = 0.5;
  blend.baseColor = {0.8, 0.5, 0.3};
  DisneyParams coated = glass(0.6, 2.5);
  coated.clearcoat = 1;
  const Case cases[] = {{"glass 0.3 outside", glass(0.3, 1.5), 40},
                        {"glass 0.3 inside", glass(0.3, 1.5), 150},
                        {"glass 0.8 grazing", glass(0.8, 1.25), 85},
                        {"glass 0.3 inside beyond critical", glass(0.3, 1.5), 120},
                        {"blend 0.5", blend, 30},
                        {"coated ior 2.5 inside", coated, 160}};
  std::uint64_t seed = 300;
  for (const Case &c : cases) {
    for (const bool square : {false, true}) {
      const DisneyBrdf m(c.p);
      const Vec3 wo = fromAngles(c.theta, 25);
      const double eta = wo.z > 0 ? c.p.ior : 1 / c.p.ior;
      test::Peak peak = test::peakAt(Vec3{-wo.x, -wo.y, wo.z});
      peak.y.push_back(1.0);
      const Vec3 up{wo.x, wo.y, std::abs(wo.z)};
      if (const auto t = refract(up, {0, 0, 1}, eta)) {
        const Point2 q = spherePoint(wo.z > 0 ? *t : Vec3{t->x, t->y, -t->z});
        peak.x.push_back(q.x), peak.y.push_back(q.y);
      }
      const auto r = test::testDirections(
          [&](Point2 u) -> std::optional<Vec3> {
            const auto s = square ? m.sampleSquare(wo, u) : m.sample(wo, test::choiceOf(u), u);
            if (!s) return std::nullopt;
            return s->wi;
          },
          [&](Vec3 wi) { return m.pdf(wo, wi); }, 400000, seed++, peak, 80, 80, true);
      EXPECT_GT(r.chi.pValue, test::sidakLevel()) << c.name << ": " << r.describe();
      EXPECT_LE(r.pdfMass, 1 + 1e-4) << c.name;
      const double missing = std::max(0.0, 1 - r.pdfMass);
      EXPECT_NEAR(r.failedFraction, missing, 5 * std::sqrt(missing / 400000) + 1e-4)
          << c.name << (square ? " (square)" : "") << ": " << r.describe();
    }
  }
}

TEST(Dielectric, SampleCarriesTheFullEvalAndPdfAndDeltasTheirWeight) {
  Rng rng(7);
  for (const double roughness : {0.0, 0.3})
    for (int k = 0; k < 2000; ++k) {
      DisneyParams p = glass(roughness, 1.5);
      p.specTrans = 0.7;
      const DisneyBrdf m(p);
      const Vec3 wo = fromAngles(180 * rng.uniform(), 360 * rng.uniform());
      const auto s = m.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()});
      if (!s) continue;
      if (s->delta) {
        EXPECT_EQ(roughness, 0);
        EXPECT_EQ(s->misPdf, std::numeric_limits<double>::infinity());
        // Mirror or refraction of wo about the normal.
        EXPECT_NEAR(s->wi.x * wo.x + s->wi.y * wo.y,
                    -(wo.x * wo.x + wo.y * wo.y) *
                        (s->wi.z * wo.z > 0 ? 1 : 1 / (wo.z > 0 ? 1.5 : 1 / 1.5)),
                    1e-9);
        continue;
      }
      const BsdfValue v = m.evalWithPdf(wo, s->wi);
      EXPECT_NEAR(v.pdf, s->pdf, 1e-9 * s->pdf);
      EXPECT_NEAR(m.pdf(wo, s->wi), s->pdf, 1e-9 * s->pdf);
      EXPECT_NEAR(v.f.r, s->f.r, 1e-9 * std::abs(s->f.r) + 1e-300);
      EXPECT_NEAR(m.eval(wo, s->wi).b, s->f.b, 1e-9 * std::abs(s->f.b) + 1e-300);
      // The lobe API composes into eval.
      Rgb sum;
      for (int l = 0; l < m.lobeCount(); ++l) sum += m.evalLobe(l, wo, s->wi);
      EXPECT_NEAR(sum.g, s->f.g, 1e-9 * std::abs(s->f.g) + 1e-300);
    }
}

TEST(Dielectric, StiffCasesStayFinite) {
  Rng rng(5);
  for (const double ior : {1.0001, 1.5, 2.5, 4.0})
    for (const double roughness : {0.0, 0.001, 0.05, 1.0}) {
      const DisneyBrdf m(glass(roughness, ior));
      for (int k = 0; k < 3000; ++k) {
        // Grazing views and directions on both sides, and exact ones.
        const double zo = k % 3 == 0 ? (k % 2 ? 1e-9 : -1e-9) : 2 * rng.uniform() - 1;
        const double r = std::sqrt(std::max(0.0, 1 - zo * zo));
        const Vec3 wo{r, 0, zo};
        const Vec3 wi = k % 5 == 0 ? Vec3{-wo.x, -wo.y, -wo.z}
                                   : sphereDirection({rng.uniform(), rng.uniform()});
        const BsdfValue v = m.evalWithPdf(wo, wi);
        ASSERT_TRUE(v.f.isFinite() && std::isfinite(v.pdf) && v.pdf >= 0)
            << "ior " << ior << " roughness " << roughness << " wo.z " << zo;
        if (const auto s = m.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()})) {
          ASSERT_TRUE(s->f.isFinite() && std::isfinite(s->pdf) && s->pdf > 0 && isFinite(s->wi))
              << "ior " << ior << " roughness " << roughness << " wo.z " << zo;
          ASSERT_NEAR(length(s->wi), 1, 1e-9);
        }
      }
    }
}

TEST(Dielectric, ParametersAreValidated) {
  DisneyParams p = glass(0.1, 1.0);
  EXPECT_THROW(DisneyBrdf{p}, std::invalid_argument);
  p.ior = 4.5;
  EXPECT_THROW(DisneyBrdf{p}, std::invalid_argument);
  p.ior = 1.5;
  p.specTrans = 1.5;
  EXPECT_THROW(DisneyBrdf{p}, std::invalid_argument);
  // Without transmission the material still reflects only, as before.
  const DisneyBrdf opaque{DisneyParams{}};
  EXPECT_FALSE(opaque.transmits());
  EXPECT_EQ(opaque.lobeCount(), 3);
  EXPECT_TRUE(opaque.eval({0, 0, 1}, {0, 0, -1}).isBlack());
  EXPECT_EQ(opaque.pdf({0, 0, -1}, {0, 0, 1}), 0);
}

}  // namespace
}  // namespace nuld
