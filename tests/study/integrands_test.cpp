// The integration study's integrands (tools/study/integrands.h): every
// integrand's reference against an independent quadrature, a black map
// refused, and the lobe choice changing only the BRDF's own sampling.
#include "tools/study/integrands.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "materials/disney_target.h"
#include "materials/sphere_map.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/target_spec.h"
#include "tests/study/synthetic_map.h"
#include "tools/study/integration_study.h"

namespace nuld::study {
namespace {

using test::syntheticMap;
constexpr double kPi = std::numbers::pi;

// The sphere integral of g by the midpoint rule in (phi, theta) with s
// steps per map pixel and the sin theta Jacobian: another parameterization
// than the references' (z = cos theta) and another rule. Pixel edges are
// step edges, so the error is the smooth O(h^2) of the midpoint rule plus
// the kinks of max(0, n.w), also O(h^2).
double thetaPhiQuadrature(const StudyEnvmap &map, int s, const std::function<double(Vec3)> &g) {
  const int W = map.width * s, H = map.height * s;
  double sum = 0;
  for (int j = 0; j < H; ++j) {
    const double theta = kPi * (j + 0.5) / H;
    double row = 0;
    for (int i = 0; i < W; ++i) {
      const double phi = 2 * kPi * (i + 0.5) / W;
      const Vec3 w{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                   std::cos(theta)};
      row += g(w) * map.luminance[std::size_t(j / s) * map.width + i / s];
    }
    sum += row * std::sin(theta);
  }
  return sum * (kPi / H) * (2 * kPi / W);
}

// The integral over the square of `integrand.f` equals the reference
// (checks the 4 pi convention); oracle at two resolutions: the midpoint
// rule's O(h^2) error at the finer one is about a third of their
// difference, so the reference must lie within twice that difference.
void expectMatchesThetaPhi(const Integrand &in, const StudyEnvmap &map,
                           const std::function<double(Vec3)> &g) {
  const double coarse = thetaPhiQuadrature(map, 48, g), fine = thetaPhiQuadrature(map, 96, g);
  EXPECT_NEAR(in.reference, fine, 2 * std::abs(fine - coarse) + 1e-12 * fine) << in.name;
  EXPECT_LT(std::abs(in.reference - fine), 1e-4 * in.reference) << in.name;
  EXPECT_LT(in.referenceError, 1e-7 * in.reference) << in.name;
}

TEST(IntegrationStudyIntegrands, GaussLegendreIsExactForPolynomials) {
  std::vector<double> x, w;
  gaussLegendre(5, x, w);
  double p8 = 0, p9 = 0;  // degree <= 2q - 1 = 9 is exact
  for (int i = 0; i < 5; ++i) {
    p8 += w[i] * std::pow(x[i], 8);
    p9 += w[i] * std::pow(x[i], 9);
  }
  EXPECT_NEAR(p8, 2.0 / 9, 1e-14);
  EXPECT_NEAR(p9, 0.0, 1e-14);
}

TEST(IntegrationStudyIntegrands, GaussianStepReferenceMatchesQuadrature) {
  const Integrand in = makeGaussianStep();
  // Midpoint rule over [0, 0.6] x [0, 1] (the step edge is a grid edge):
  // error about h^2 / 24 max|f''| ~ (1e-3)^2 / 24 * 1e3 < 1e-7.
  const int nx = 600, ny = 1000;
  double sum = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) sum += in.f({0.6 * (i + 0.5) / nx, (j + 0.5) / ny});
  EXPECT_NEAR(in.reference, sum * 0.6 / (double(nx) * ny), 1e-6);
  EXPECT_GT(in.reference, 0.6);  // more than half of the mass lies left of 0.6
  EXPECT_LT(in.reference, 0.9);
}

TEST(IntegrationStudyIntegrands, QuarterDiscBilinearReferenceMatchesPolarQuadrature) {
  const Integrand in = makeQuarterDiscBilinear();
  // Midpoint rule in polar coordinates (r, theta): no boundary inside the
  // cells, smooth integrand, error O(h^2) ~ 1e-6 at 1000 x 1000.
  const int nr = 1000, nt = 1000;
  double sum = 0;
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < nt; ++j) {
      const double r = (i + 0.5) / nr, t = 0.5 * kPi * (j + 0.5) / nt;
      sum += in.f({r * std::cos(t), r * std::sin(t)}) * r;
    }
  EXPECT_NEAR(in.reference, sum * (1.0 / nr) * (0.5 * kPi / nt), 1e-5);
}

TEST(IntegrationStudyIntegrands, EnvmapCosReferenceMatchesThetaPhiQuadrature) {
  const auto map = makeStudyEnvmap(syntheticMap(), "test", "synthetic");
  const Vec3 n = envmapCosNormal();
  const Integrand in = makeEnvmapCos(map);
  EXPECT_EQ(in.name, "envmap:test*cos");
  expectMatchesThetaPhi(in, *map, [&](Vec3 w) { return std::max(0.0, dot(n, w)); });
}

TEST(IntegrationStudyIntegrands, DisneyEnvmapReferenceMatchesThetaPhiQuadrature) {
  const auto map = makeStudyEnvmap(syntheticMap(), "test", "synthetic");
  const Integrand in = makeDisneyEnvmap(map);
  EXPECT_EQ(in.name, "disney*envmap:test");
  EXPECT_EQ(in.target->spec(), "disney");
  const DisneyBrdf brdf(supplementDisneyParams());
  const Vec3 wo = supplementWo();
  expectMatchesThetaPhi(in, *map,
                        [&](Vec3 w) { return w.z > 0 ? brdf.eval(wo, w).luminance() * w.z : 0.0; });
}

TEST(IntegrationStudyIntegrands, BlackMapIsRefused) {
  Image black{4, 2, 3, std::vector<float>(4 * 2 * 3, 0.0f)};
  EXPECT_THROW(makeStudyEnvmap(black, "black", "black.exr"), std::invalid_argument);
}

// The smooth-light lobe integrand's reference against a plain midpoint rule
// on the unit square (1024 x 1024, through f = 4 pi g), a quadrature that
// shares nothing with it but the integrand: the two agree to 1e-4.
TEST(IntegrationStudyIntegrands, DisneyCosinesReferenceMatchesMidpointQuadrature) {
  for (double theta : disneyCosinesThetas()) {
    const Integrand in = makeDisneyCosines(theta);
    EXPECT_LT(in.referenceError, 1e-6 * in.reference);
    constexpr int kCells = 1024;
    double sum = 0;
    for (int j = 0; j < kCells / 2; ++j)  // the upper hemisphere is v < 1/2
      for (int i = 0; i < kCells; ++i) sum += in.f({(i + 0.5) / kCells, (j + 0.5) / kCells});
    EXPECT_NEAR(sum / (double(kCells) * kCells), in.reference, 1e-4 * in.reference) << in.name;
  }
}

// --lobe-choice changes only the BRDF's own lobe sampling (the sobol-lobes
// row): the same integrand, target and reference under either choice, and a
// different estimate from the same primary points; the choice is one of the
// row options, so a rerun with the other is refused.
TEST(IntegrationStudyIntegrands, LobeChoiceChangesOnlyTheBrdfsOwnSampling) {
  const Integrand albedo = makeDisneyCosines(45, supplementDisneyParams(), LobeChoice::Albedo);
  const Integrand uniform = makeDisneyCosines(45, supplementDisneyParams(), LobeChoice::Uniform);
  EXPECT_EQ(albedo.reference, uniform.reference);
  EXPECT_EQ(albedo.target->spec(), uniform.target->spec());
  int differ = 0;
  for (int k = 0; k < 64; ++k) {
    const Point2 u{(k + 0.5) / 64, std::fmod(0.618034 * k + 0.3, 1.0)};
    EXPECT_EQ(albedo.f(u), uniform.f(u));
    differ += albedo.lobeContribution(u) != uniform.lobeContribution(u);
  }
  EXPECT_GT(differ, 32);
  IntegrateOptions o;
  o.lobeChoice = LobeChoice::Uniform;
  EXPECT_NE(rowOptions(o).find("lobe-choice=uniform"), std::string::npos);
  EXPECT_NE(rowOptions(o), rowOptions(IntegrateOptions{}));
}

}  // namespace
}  // namespace nuld::study
