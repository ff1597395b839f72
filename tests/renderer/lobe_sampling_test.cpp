// BSDF sampling through tabulated lobes: the tables and their frames
// (renderer/lobe_tables.h), the sobol-tabulated backend, lobe banks served by
// the bank backend, and the BSDF-only estimator.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numbers>

#include "backends/backend_registry.h"
#include "backends/bank_backend.h"
#include "materials/disney.h"
#include "materials/lambertian.h"
#include "materials/sphere_map.h"
#include "renderer/lobe_tables.h"
#include "renderer/render.h"
#include "renderer/shapes.h"
#include "sampler/sequences/rng.h"
#include "tests/common/chi_square.h"
#include "tests/renderer/test_scenes.h"

namespace nuld {
namespace {

using test::constantMap;
using test::sceneWith;

constexpr double kPi = std::numbers::pi;
// Density by estimator (for RenderSettings), and f cos (for LobeTables);
// every bin served by its table (these tests are about the tables; the route
// measurement has its own, lobe_routes_test.cpp). The render settings take
// a defensive share (the default has none) so that the mixture is rendered
// too; the tables alone have none.
const LobeTableSettings kSmallTables{4, 2, 64, std::nullopt, LobeRouting::Table, 0.05};
const LobeTableSettings kSmallProductTables{4, 2, 64, 0.0, LobeRouting::Table, 0.0};

std::shared_ptr<const DisneyBrdf> disney(double anisotropic, double roughness = 0.4) {
  DisneyParams p;
  p.roughness = roughness;
  p.metallic = 0.3;
  p.anisotropic = anisotropic;
  return std::make_shared<DisneyBrdf>(p);
}

Vec3 direction(double thetaDegrees, double phiDegrees) {
  const double t = thetaDegrees * kPi / 180, p = phiDegrees * kPi / 180;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

double meanOf(const Image &img) {
  double s = 0;
  for (float v : img.pixels) s += v;
  return s / double(img.pixels.size());
}

TEST(LobeTables, OneSetOfBinsPerDistinctDisneyMaterial) {
  const auto iso = disney(0), aniso = disney(0.5);
  const LobeTables tables({iso, std::make_shared<Lambertian>(Rgb::grey(0.5)), iso, aniso},
                          kSmallProductTables);
  EXPECT_EQ(tables.materials(), 2u);
  EXPECT_EQ(tables.targets().size(), 4u + 4u * 2u);  // theta bins, times phi bins if anisotropic
  EXPECT_FALSE(tables.frame(nullptr, {0, 0, 1}));
  EXPECT_FALSE(tables.frame(iso.get(), {0, 0, -1}));  // below the surface
  // The bin's table is the lobe at the bin's centre: theta 33.75 for 30.
  const auto f = tables.frame(iso.get(), direction(30, 0));
  ASSERT_TRUE(f);
  EXPECT_NE(f->table->spec().find("theta=33.75"), std::string::npos) << f->table->spec();
  EXPECT_THROW(LobeTables({iso}, LobeTableSettings{0, 1, 64, 0.0}), std::invalid_argument);
  EXPECT_THROW(LobeTables({iso}, LobeTableSettings{4, 1, 64, 1.5}), std::invalid_argument);
  EXPECT_THROW(LobeTables({iso}, kSmallTables), std::invalid_argument);  // no mix
}

// The density handed back for a direction is the table's density at the
// point it came from, in every frame (rotation, folds).
TEST(LobeTables, PdfOfADrawnDirectionIsTheTablesDensityThere) {
  const auto iso = disney(0), aniso = disney(0.6);
  const LobeTables tables({iso, aniso}, kSmallProductTables);
  Rng rng(7);
  for (const auto &m : {iso, aniso})
    for (const Vec3 wo : {direction(10, 0), direction(50, 130), direction(80, -100)}) {
      const LobeFrame f = *tables.frame(m.get(), wo);
      for (int i = 0; i < 2000; ++i) {
        const Point2 x{rng.uniform(), 0.5 * rng.uniform()};
        const Vec3 wi = f.direction(x);
        EXPECT_NEAR(length(wi), 1, 1e-12);
        const double expected = f.table->pdf(x) * kInvFourPi;
        ASSERT_NEAR(f.tablePdf(wi), expected, 1e-9 * expected) << x.x << " " << x.y;
      }
      EXPECT_EQ(f.tablePdf({0, 0, -1}), 0);
    }
}

// Chi-square of the directions drawn through a frame (the table's inverse
// CDF, then the frame) against the frame's pdf, in bins of (phi, cos theta)
// of the shading frame: exercises the rotation of isotropic lobes and the
// folds of anisotropic ones at several view directions.
TEST(LobeTables, DrawnDirectionsFollowTheFramesPdf) {
  const auto iso = disney(0), aniso = disney(0.6, 0.25);
  const LobeTables tables({iso, aniso}, kSmallProductTables);
  // Bin and sub-sample edges fall on the 64 x 32 tables' cell edges, so the
  // expected counts of the piecewise constant pdf are exact: the folds keep
  // the edges in place, and for an isotropic lobe (rotated to wo's azimuth)
  // azimuths are binned relative to wo's.
  constexpr int kPhi = 16, kZ = 8, kSub = 16, kSamples = 100000;
  const double level = test::sidakLevel(0.01, 6);
  Rng rng(3);
  for (const auto &m : {iso, aniso})
    for (const Vec3 wo : {direction(20, 130), direction(45, -60), direction(70, 200)}) {
      const LobeFrame f = *tables.frame(m.get(), wo);
      const double phiO = m->params().anisotropic > 0 ? 0 : std::atan2(wo.y, wo.x);
      std::vector<double> observed(kPhi * kZ, 0), expected(kPhi * kZ, 0);
      for (int i = 0; i < kSamples; ++i) {
        const Vec3 wi = f.direction(f.table->invert({rng.uniform(), rng.uniform()}).x);
        if (!(wi.z > 0)) continue;
        const double phi = (std::atan2(wi.y, wi.x) - phiO) / (2 * kPi);
        const int bx = std::min(kPhi - 1, int((phi - std::floor(phi)) * kPhi));
        const int bz = std::min(kZ - 1, int(wi.z * kZ));
        observed[bz * kPhi + bx] += 1;
      }
      for (int bz = 0; bz < kZ; ++bz)
        for (int bx = 0; bx < kPhi; ++bx)
          for (int sz = 0; sz < kSub; ++sz)
            for (int sx = 0; sx < kSub; ++sx) {
              const double z = (bz + (sz + 0.5) / kSub) / kZ;
              const double phi = phiO + 2 * kPi * (bx + (sx + 0.5) / kSub) / kPhi;
              const double r = std::sqrt(1 - z * z);
              // d omega = d phi d z
              expected[bz * kPhi + bx] += f.tablePdf({r * std::cos(phi), r * std::sin(phi), z}) *
                                          (2 * kPi / kPhi / kSub) * (1.0 / kZ / kSub) * kSamples;
            }
      const test::ChiSquare c = test::pooledChiSquare(observed, expected);
      EXPECT_GT(c.pValue, level) << c.note << " anisotropic " << m->params().anisotropic << " wo "
                                 << wo.x << "," << wo.y << "," << wo.z;
    }
}

// A Disney sphere under a constant sky: BSDF sampling through the material's
// mapping, BSDF sampling through the tabulated lobes, light sampling and MIS
// of light and tabulated-lobe sampling estimate the same image.
TEST(LobeSampling, EveryEstimatorAgreesUnderAConstantSky) {
  const Scene scene = sceneWith({test::unitSphere()}, {disney(0.5)}, constantMap(1.0f),
                                {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40, false});
  const auto run = [&](const std::string &backend, IntegratorKind kind) {
    RenderSettings s{12, 12, 1024, kind, 1};
    s.lobeTables = kSmallTables;
    auto b = makeBackend(backend, 11);
    RenderStats stats;
    const Image img = render(scene, s, *b, &stats);
    EXPECT_EQ(stats.rejectedSamples, 0u);
    EXPECT_EQ(stats.classicFallbacks, 0u);
    return img;
  };
  const Image light = run("sobol", IntegratorKind::Light);
  const double reference = meanOf(light);
  EXPECT_GT(reference, 0.3);
  for (const auto &[backend, kind] : {std::pair{"sobol", IntegratorKind::Bsdf},
                                      {"sobol-tabulated", IntegratorKind::Bsdf},
                                      {"sobol-tabulated", IntegratorKind::Direct},
                                      {"sobol-tabulated", IntegratorKind::Path}}) {
    const Image img = run(backend, kind);
    for (float v : img.pixels) ASSERT_TRUE(std::isfinite(v));
    // A convex sphere sees no other surface, so the path estimate is the
    // direct one too.
    EXPECT_NEAR(meanOf(img), reference, 0.005 * reference) << backend << " " << toString(kind);
  }
}

// The tables' density follows the estimator unless given: f cos for BSDF
// sampling alone, the material's sampling pdf under MIS; the routes are
// measured under MIS for the direct integrator alone. Both are derived, and
// the user's settings pass through as set.
TEST(LobeSampling, TableDensityFollowsTheEstimator) {
  RenderSettings s;
  s.integrator = IntegratorKind::Bsdf;
  EXPECT_EQ(lobeTablesFor(s).samplingMix, 0.0);
  EXPECT_FALSE(lobeTablesFor(s).underMis);
  for (const auto kind : {IntegratorKind::Direct, IntegratorKind::Path}) {
    s.integrator = kind;
    EXPECT_EQ(lobeTablesFor(s).samplingMix, 1.0);
    EXPECT_EQ(lobeTablesFor(s).underMis, kind == IntegratorKind::Direct);
    EXPECT_EQ(lobeTablesFor(s).settings, s.lobeTables);
  }
  s.lobeTables.samplingMix = 0.25;
  EXPECT_EQ(lobeTablesFor(s).samplingMix, 0.25);
  const auto m = disney(0);
  EXPECT_NE(LobeTables({m}, lobeTablesFor(s)).targets()[0]->spec().find("mix=0.25"),
            std::string::npos);
}

// The power heuristic's two weights of one direction sum to one, at any
// ratio of the pdfs, even where their squares underflow.
TEST(LobeSampling, MisWeightsSumToOne) {
  for (double a : {1e-300, 1e-6, 0.3, 1.0, 7.0, 1e8})
    for (double b : {1e-300, 1e-6, 0.3, 1.0, 7.0, 1e8})
      EXPECT_NEAR(powerHeuristic(a, b) + powerHeuristic(b, a), 1.0, 1e-12) << a << " " << b;
}

// Two spheres in two Disney materials and a bank of lobe sets for the left
// one's tables only: the right sphere's tables are declined, counted, and
// rendered bit for bit as sobol-tabulated renders them; the left sphere's
// differ.
TEST(LobeSampling, ABankForOneMaterialLeavesTheOtherAsSobolTabulated) {
  const auto left = disney(0), right = disney(0.5, 0.7);
  Scene scene =
      sceneWith({makeSphere({-1.6, 0, 0}, 1.0, 16, 32, "left"),
                 makeSphere({1.6, 0, 0}, 1.0, 16, 32, "right")},
                {left, right}, constantMap(0.8f), {{0, 0, 7}, {0, 0, 0}, {0, 1, 0}, 45, false});
  constexpr std::size_t kSpp = 8;
  RenderSettings s{32, 12, kSpp, IntegratorKind::Direct, 1};
  s.lobeTables = kSmallTables;
  const LobeTables tables({left}, lobeTablesFor(s));
  std::vector<SetBank> banks;
  Rng rng(5);
  for (const Target *t : tables.targets()) {
    SetBank b{PointSet{}, "test bank"};
    b.sets.n = kSpp;
    for (std::size_t i = 0; i < 4 * kSpp; ++i)
      b.sets.points.push_back(t->invert({rng.uniform(), rng.uniform()}).x);
    b.sets.metadata["target"] = t->spec();
    banks.push_back(std::move(b));
  }
  BankBackend bank("optimized:test", banks, 21);
  ASSERT_TRUE(bank.samplesLobes());
  RenderStats bankStats;
  const Image withBank = render(scene, s, bank, &bankStats);
  EXPECT_EQ(bank.servedTargets(), tables.targets().size());
  auto sobol = makeBackend("sobol-tabulated", 21);
  const Image plain = render(scene, s, *sobol);

  // The image's right part sees only the right sphere (and the sky), its left
  // part only the left one.
  std::size_t sameRight = 0, rightPixels = 0, differentLeft = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const bool same = withBank.at(x, y, 0) == plain.at(x, y, 0) &&
                        withBank.at(x, y, 1) == plain.at(x, y, 1) &&
                        withBank.at(x, y, 2) == plain.at(x, y, 2);
      if (x >= s.width / 2 + 1) {
        ++rightPixels;
        sameRight += same;
      } else if (x < s.width / 2 - 1) {
        differentLeft += !same;
      }
    }
  EXPECT_EQ(sameRight, rightPixels);
  EXPECT_GT(differentLeft, 20u);
  // The right sphere's tables, which no bank serves, take Owen-Sobol
  // through the table: no sample falls back to the material's own sampler,
  // and the backend counts them as fallbacks.
  EXPECT_EQ(bankStats.classicFallbacks, 0u);
  EXPECT_GT(bank.report().pairUse[1].fellBack, 0u);
  for (float v : withBank.pixels) EXPECT_TRUE(std::isfinite(v));
}

// A bank of one set is as unrandomized as a bank can be: unshifted, every
// pixel gets the same points. shifted:PATHS pulls them back to primary
// space and shifts them per pixel, so over pixels every point follows the
// table exactly: chi-square of 4000 pixels' points against the table's box
// masses passes shifted and fails unshifted.
TEST(LobeSampling, ShiftedBanksFollowTheTableOverPixels) {
  const auto material = disney(0.0, 0.3);
  const LobeTables tables({material}, kSmallProductTables);
  const Target &table = *tables.targets()[1];
  constexpr std::size_t kN = 8;
  SetBank bank{PointSet{}, "one set"};
  bank.sets.n = kN;
  Rng rng(2);
  for (std::size_t i = 0; i < kN; ++i)
    bank.sets.points.push_back(table.invert({(i + rng.uniform()) / kN, rng.uniform()}).x);
  bank.sets.metadata["target"] = table.spec();
  constexpr int kX = 8, kY = 4;
  std::vector<double> expected(kX * kY);
  for (int j = 0; j < kY; ++j)
    for (int i = 0; i < kX; ++i)
      expected[j * kX + i] =
          table.mass({{double(i) / kX, 0.5 * j / kY}, {double(i + 1) / kX, 0.5 * (j + 1) / kY}}) *
          4000.0 * kN;
  for (const bool shifted : {true, false}) {
    BankBackend backend("test", {bank}, 3, 0x6f7074696d697a65ull, shifted);
    backend.prepare(kN, {nullptr, tables.targets()});
    std::vector<double> observed(kX * kY, 0);
    std::vector<Point2> out(kN);
    for (std::uint64_t pixel = 0; pixel < 4000; ++pixel) {
      ASSERT_TRUE(backend.distributed(table, pixel, SampleLayout::bsdf(0), out));
      for (const Point2 &p : out) {
        ASSERT_GT(table.pdf(p), 0);
        observed[std::min(kY - 1, int(p.y * 2 * kY)) * kX + std::min(kX - 1, int(p.x * kX))] += 1;
      }
    }
    const test::ChiSquare c = test::pooledChiSquare(observed, expected);
    if (shifted)
      EXPECT_GT(c.pValue, 0.01) << c.note;
    else
      EXPECT_LT(c.pValue, 1e-6);
  }
}

TEST(LobeSampling, DeterministicForAnyThreadCount) {
  const Scene scene = sceneWith({test::unitSphere()}, {disney(0.3)}, constantMap(1.0f),
                                {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40, false});
  RenderSettings s{24, 20, 8, IntegratorKind::Path, 4};
  s.lobeTables = kSmallTables;
  Image one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = render(scene, s, *makeBackend("sobol-tabulated", 9));
  }
  EXPECT_EQ(one.pixels, render(scene, s, *makeBackend("sobol-tabulated", 9)).pixels);
}

}  // namespace
}  // namespace nuld
