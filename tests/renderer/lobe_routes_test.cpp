// BSDF sampling routes (renderer/lobe_tables.h; renderer/README.md, "Lobe
// routes"): the defensive mixture's samples against its pdf, the bound on
// its weights, the route measurement, the table cache, and renders of a
// glossy anisotropic metal that every backend must agree on.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "backends/backend_registry.h"
#include "backends/bank_backend.h"
#include "materials/disney.h"
#include "materials/sphere_map.h"
#include "renderer/lobe_tables.h"
#include "renderer/path_integrator.h"
#include "renderer/render.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"
#include "tests/materials/chi_square.h"
#include "tests/renderer/lobe_cases.h"
#include "tests/renderer/test_scenes.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;

Vec3 direction(double thetaDegrees, double phiDegrees) {
  const double t = thetaDegrees * kPi / 180, p = phiDegrees * kPi / 180;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

using test::everyBin;
using test::material;

// The route's directions, drawn as the path integrator draws them (the
// defensive split of a uniform primary point, then the table's inverse CDF
// or the material's sampler), against the mixture pdf the route reports, from a
// sharp mirror to a rough lobe, anisotropic, up to grazing views.
TEST(LobeRoutes, RouteSamplesFollowTheMixturePdf) {
  constexpr int kSamples = 200000;
  struct Case {
    double roughness, anisotropic, metallic, theta, phi;
  };
  std::vector<Case> cases;
  for (const double r : {0.01, 0.2, 0.5, 1.0}) {
    cases.push_back({r, 0.0, 1.0, 45, 0});
    cases.push_back({r, 0.9, 0.0, 89, 30});
  }
  const double level = test::sidakLevel(0.01, int(cases.size()));
  std::uint64_t seed = 77;
  for (const Case &c : cases) {
    const auto m = material(c.roughness, c.anisotropic, c.metallic);
    const LobeTables tables({m}, everyBin(0.25));
    const Vec3 wo = direction(c.theta, c.phi);
    const LobeFrame lobe = *tables.frame(m.get(), wo);
    // Test bins on the tables' cell edges (64 x 32 over the hemisphere);
    // the folds of an anisotropic frame keep those edges in place.
    const auto t = test::testDirections(
        [&](Point2 u) -> std::optional<Vec3> {
          const auto s = sampleRoute(*m, wo, lobe, {u}, test::choiceOf(u));
          return s ? std::optional<Vec3>(s->wi) : std::nullopt;
        },
        [&](Vec3 wi) { return lobe.pdf(wi, m->pdf(wo, wi)); }, kSamples, seed++,
        test::peakAt(reflect(wo, Vec3{0, 0, 1})), 64, 32);
    const std::string name = "roughness " + std::to_string(c.roughness) + " anisotropic " +
                             std::to_string(c.anisotropic) + " theta " + std::to_string(c.theta);
    EXPECT_GT(t.chi.pValue, level) << name << ": " << t.describe();
    EXPECT_EQ(t.belowFraction, 0) << name;
    const double missing = std::max(0.0, 1 - t.pdfMass);
    EXPECT_NEAR(t.failedFraction, missing, 5 * std::sqrt(missing / kSamples) + 2e-5)
        << name << ": " << t.describe();
  }
}

// The documented bound: a tabulated sample's weight f cos / p is at most
// 1 / defensive times the material's own weight at the same direction, over
// roughness 0.01 to 1, anisotropy 0 to 0.9, metallic 0 and 1 and views up
// to 89 degrees; and it is finite. Also, the largest weight a route gives is
// at most 1 / defensive times the largest the material's own sampler gives.
TEST(LobeRoutes, WeightsStayWithinTheDefensiveBound) {
  constexpr double kDefensive = 0.1;
  Rng rng(11);
  for (const double roughness : {0.01, 0.05, 0.2, 0.5, 1.0})
    for (const double anisotropic : {0.0, 0.5, 0.9})
      for (const double metallic : {0.0, 1.0}) {
        const auto m = material(roughness, anisotropic, metallic);
        const LobeTables tables({m}, everyBin(kDefensive, 32));
        for (const double theta : {0.0, 30.0, 60.0, 80.0, 89.0})
          for (const double phi : {0.0, 37.0}) {
            const Vec3 wo = direction(theta, phi);
            const LobeFrame lobe = *tables.frame(m.get(), wo);
            double routeMax = 0, ownMax = 0;
            for (int i = 0; i < 400; ++i) {
              const Point2 u{rng.uniform(), rng.uniform()};
              const double uc = rng.uniform();
              if (const auto own = m->sample(wo, uc, u))
                ownMax = std::max(ownMax, own->f.luminance() * own->wi.z / own->pdf);
              const auto route = sampleRoute(*m, wo, lobe, {u}, uc);
              if (!route) continue;
              const BsdfSample &s = *route;
              EXPECT_NEAR(route->misPdf, m->pdf(wo, s.wi), 1e-12 * route->misPdf);
              const double w = s.f.luminance() * s.wi.z / s.pdf;
              const double own = s.f.luminance() * s.wi.z / route->misPdf;
              ASSERT_TRUE(std::isfinite(w));
              ASSERT_LE(w, own / kDefensive * (1 + 1e-9))
                  << "roughness " << roughness << " anisotropic " << anisotropic << " metallic "
                  << metallic << " theta " << theta;
              routeMax = std::max(routeMax, w);
            }
            // The material's own largest weight, over its samples and the
            // route's directions (its weight there bounds the route's).
            EXPECT_LE(routeMax, std::max(ownMax, routeMax * kDefensive) / kDefensive * (1 + 1e-9));
          }
      }
}

// Without a defensive share the route is the table alone (the point its
// inverse CDF gives, the table's density); a share of 1 is the material's
// own sampler at the same primary point, with its own pdf.
TEST(LobeRoutes, DefensiveShareOfZeroAndOneAreTheTwoRoutes) {
  const auto m = material(0.3, 0.4, 0.5);
  const Vec3 wo = direction(40, 20);
  for (const double d : {0.0, 1.0}) {
    const LobeTables tables({m}, everyBin(d));
    const LobeFrame lobe = *tables.frame(m.get(), wo);
    Rng rng(5);
    for (int i = 0; i < 200; ++i) {
      const Point2 u{rng.uniform(), rng.uniform()};
      const double uc = rng.uniform();
      const auto route = sampleRoute(*m, wo, lobe, {u}, uc);
      if (d == 1) {
        const auto own = m->sample(wo, uc, u);
        ASSERT_EQ(bool(route), bool(own));
        if (!route) continue;
        EXPECT_EQ(route->wi.x, own->wi.x);
        EXPECT_NEAR(route->pdf, own->pdf, 1e-12 * own->pdf);
      } else {
        ASSERT_TRUE(route);
        const BsdfSample &s = *route;
        const Point2 x = lobe.table->invert(u).x;
        EXPECT_EQ(s.wi.x, lobe.direction(x).x);
        EXPECT_NEAR(s.pdf, lobe.tablePdf(s.wi), 1e-9 * s.pdf);
      }
      // Either way the MIS weights take the material's pdf at the direction.
      if (route) EXPECT_NEAR(route->misPdf, m->pdf(wo, route->wi), 1e-12 * route->misPdf);
    }
  }
}

// A point that follows the table (as a lobe bank deals it) gives the sample
// its primary point (GridTarget::primaryOf) gives: used as it is without a
// defensive share, pulled back and split with one; a point in a cell the
// table cannot draw from (the lower hemisphere's, density 0) is pulled back
// to a point it can.
TEST(LobeRoutes, APointThatFollowsTheTableGivesItsPrimaryPointsSample) {
  const auto m = material(0.4, 0.3, 0.2);
  const Vec3 wo = direction(35, 10);
  for (const double d : {0.0, 0.1}) {
    const LobeTables tables({m}, everyBin(d));
    const LobeFrame lobe = *tables.frame(m.get(), wo);
    Rng rng(9);
    int drawn = 0;
    for (int i = 0; i < 500; ++i) {
      const Point2 x = lobe.table->invert({rng.uniform(), rng.uniform()}).x;
      const auto fromPoint = sampleRoute(*m, wo, lobe, {x, true}, 0.5);
      const auto fromPrimary = sampleRoute(*m, wo, lobe, {lobe.table->primaryOf(x)}, 0.5);
      ASSERT_EQ(bool(fromPoint), bool(fromPrimary)) << d;
      if (!fromPoint) continue;
      ++drawn;
      const BsdfSample &a = *fromPoint, &b = *fromPrimary;
      EXPECT_NEAR(a.wi.x, b.wi.x, 1e-9) << d;
      EXPECT_NEAR(a.wi.y, b.wi.y, 1e-9) << d;
      EXPECT_NEAR(a.pdf, b.pdf, 1e-9 * b.pdf) << d;
      EXPECT_NEAR(fromPoint->misPdf, fromPrimary->misPdf, 1e-9 * b.pdf) << d;
    }
    EXPECT_GT(drawn, 450) << d;
    // Below the surface the table has no density: pulled back to its CDF.
    const Point2 below{0.3, 0.8};
    ASSERT_EQ(lobe.table->pdf(below), 0);
    const auto fromPoint = sampleRoute(*m, wo, lobe, {below, true}, 0.5);
    const auto fromPrimary = sampleRoute(*m, wo, lobe, {lobe.table->primaryOf(below)}, 0.5);
    ASSERT_TRUE(fromPoint && fromPrimary) << d;
    EXPECT_GT(fromPoint->wi.z, 0) << d;
    EXPECT_EQ(fromPoint->wi.x, fromPrimary->wi.x) << d;
  }
}

// The measurement hands narrow lobes back to the material's sampler (a metal
// of roughness 0.2, lte-orb's shell: alpha 0.04, whose peak moves across a
// 10-degree bin by more than its width) and keeps the tables of broad ones
// (a rough dielectric, where a table follows the lobe closely); the routes
// and targets agree.
TEST(LobeRoutes, MeasurementKeepsTheMaterialsSamplerForNarrowLobes) {
  const auto shell = material(0.2, 0.15, 1.0), rough = material(0.9, 0.0, 0.0);
  const LobeTables tables({shell, rough}, LobeTableSettings{9, 3, 256, 1.0, LobeRouting::Measured});
  std::size_t shellTabulated = 0, roughTabulated = 0, tabulated = 0;
  for (const LobeBinRoute &r : tables.routes()) {
    EXPECT_GT(r.classicVariance, 0);
    EXPECT_GT(r.tableVariance, 0);
    EXPECT_EQ(r.table, r.tableVariance <= r.classicVariance);
    (r.material == 0 ? shellTabulated : roughTabulated) += r.table;
    tabulated += r.table;
  }
  EXPECT_EQ(tables.routes().size(), 27u + 9u);
  EXPECT_EQ(tables.targets().size(), tabulated);
  EXPECT_LE(shellTabulated, 27u / 3) << "of 27 bins";
  EXPECT_GE(roughTabulated, 7u) << "of 9 bins";
  // A bin handed back has no frame: the integrator samples the material.
  for (std::size_t t = 0; t < 9; ++t) {
    const Vec3 wo = direction((t + 0.5) * 10, 0);
    EXPECT_EQ(bool(tables.frame(rough.get(), wo)), tables.routes()[27 + t].table) << t;
  }
}

// Under MIS (the direct integrator) each route is measured with a proxy
// light strategy beside it, weighted as the integrator weighs them: for the
// cup's glazed porcelain (a broad diffuse lobe under a glossy coat) light
// sampling then covers the broad lobe, so the material's own sampler's
// estimates vary less in every bin than by BSDF sampling alone; every bin's
// route is the one of least measured variance (under the uniform lobe
// choice). Which bins take a table need not agree between the two (the
// per-bin variances: tools/experiments/sample_layout.md).
TEST(LobeRoutes, RoutesUnderMisAreMeasuredWithLightSamplingBeside) {
  DisneyParams p;
  p.baseColor = {0.92, 0.9, 0.86};
  p.roughness = 0.15;
  p.clearcoat = 1;
  p.clearcoatGloss = 0.9;
  const auto glaze = std::make_shared<DisneyBrdf>(p, LobeChoice::Uniform);
  LobeTableSettings settings;
  settings.samplingMix = 1.0;
  const auto tabulated = [&](bool underMis, std::vector<double> &classic) {
    const LobeTables tables({glaze}, LobeTablesConfig(settings, underMis));
    std::size_t count = 0;
    for (const LobeBinRoute &r : tables.routes()) {
      classic.push_back(r.classicVariance);
      const double best = std::min(r.classicVariance, r.tableVariance);
      EXPECT_TRUE(std::isfinite(best) && best > 0) << r.thetaDegrees;
      const double chosen = r.table ? r.tableVariance : r.classicVariance;
      EXPECT_EQ(chosen, best) << "MIS " << underMis << " bin " << r.thetaDegrees;
      count += r.table;
    }
    return count;
  };
  std::vector<double> classicAlone, classicMis;
  const std::size_t alone = tabulated(false, classicAlone), mis = tabulated(true, classicMis);
  EXPECT_GT(alone, 0u);
  EXPECT_GT(mis, 0u);
  ASSERT_EQ(classicAlone.size(), classicMis.size());
  for (std::size_t b = 0; b < classicAlone.size(); ++b)
    EXPECT_LT(classicMis[b], classicAlone[b]) << "bin " << b;
}

TEST(LobeTableCache, BuildsTablesOncePerMaterialsAndSettings) {
  const std::vector<std::shared_ptr<const Bsdf>> materials{material(0.5, 0, 0)};
  LobeTableCache cache;
  const auto a = cache.get(materials, everyBin(0.1, 16));
  EXPECT_EQ(a, cache.get(materials, everyBin(0.1, 16)));
  EXPECT_NE(a, cache.get(materials, everyBin(0.2, 16)));
  EXPECT_NE(a, cache.get({material(0.5, 0, 0)}, everyBin(0.1, 16)));  // another material
}

// A bank for every table of `tables`: `instances` Owen-scrambled Sobol sets
// mapped through the table's inverse CDF, stand-ins for optimized sets.
// Unshifted, a bank is a fixed sample of the table, so the estimate
// converges to the mean over its points: many instances keep that close to
// the table's.
std::vector<SetBank> sobolBanks(const LobeTables &tables, std::size_t n,
                                std::size_t instances = 16) {
  std::vector<SetBank> banks;
  for (const Target *t : tables.targets()) {
    SetBank b{generatePointSet({SequenceKind::Sobol, Scramble::Owen, 17}, n, instances),
              "sobol sets"};
    for (Point2 &p : b.sets.points) p = t->invert(p).x;
    b.sets.metadata["target"] = t->spec();
    banks.push_back(std::move(b));
  }
  return banks;
}

double meanOf(const Image &img) {
  double s = 0;
  for (float v : img.pixels) s += v;
  return s / double(img.pixels.size());
}

// A glossy anisotropic metal sphere under a constant sky: every backend and
// route converges to the same mean (within 0.3 %), finite everywhere. The
// reference is BSDF sampling through the material's own sampler, whose
// weight F G2 / G1 hardly varies. The measured routes keep the material's
// own sampler in every bin of this narrow lobe (no table serves); forcing
// its tables (routing table) is unbiased too but far noisier (it converges
// at 4096 spp), so the forced tables are checked on a rougher metal, with
// their lobe banks.
TEST(LobeRoutes, GlossyAnisotropicMetalConvergesWithEveryBackend) {
  constexpr std::size_t kSpp = 1024;
  struct Case {
    double roughness;
    LobeRouting routing;
  };
  for (const Case c : {Case{0.2, LobeRouting::Measured}, Case{0.5, LobeRouting::Table}}) {
    const auto metal = material(c.roughness, 0.9, 1.0);
    // A narrow view inside the silhouette: every pixel sees the sphere, so
    // no pixel's mean depends on its coverage.
    const Scene scene = test::sceneWith({test::unitSphere()}, {metal}, test::constantMap(1.0f),
                                        {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 12, false});
    const auto run = [&](SamplerBackend &b, IntegratorKind kind, LobeTableSettings lobes) {
      RenderSettings s{12, 12, kSpp, kind, 1};
      s.lobeTables = lobes;
      RenderStats stats;
      const Image img = render(scene, s, b, &stats);
      EXPECT_EQ(stats.rejectedSamples, 0u) << b.name();
      for (float v : img.pixels) EXPECT_TRUE(std::isfinite(v)) << b.name();
      return meanOf(img);
    };
    const double reference = run(*makeBackend("sobol", 1), IntegratorKind::Bsdf, {});
    EXPECT_GT(reference, 0.2);
    LobeTableSettings routes;
    routes.routing = c.routing;
    const std::string what = toString(c.routing) + " roughness " + std::to_string(c.roughness);
    // Independent points scatter 0.3 % from seed to seed at this spp (the
    // others 0.05 %): their mean over four seeds is compared.
    for (const std::string name : {"independent", "sobol", "halton", "sobol-tabulated"})
      for (const auto kind : {IntegratorKind::Direct, IntegratorKind::Bsdf}) {
        const int seeds = name == "independent" ? 4 : 1;
        double mean = 0;
        for (int seed = 2; seed < 2 + seeds; ++seed)
          mean += run(*makeBackend(name, seed), kind, routes) / seeds;
        EXPECT_NEAR(mean, reference, 0.003 * reference)
            << name << " " << toString(kind) << " " << what;
      }
    // Lobe banks, plain and shifted, for every table that serves.
    RenderSettings s{12, 12, kSpp, IntegratorKind::Direct, 1};
    s.lobeTables = routes;
    const auto tables = scene.lobeTables->get(scene.materials, lobeTablesFor(s));
    if (c.routing == LobeRouting::Measured) {
      EXPECT_TRUE(tables->targets().empty()) << what;
      continue;
    }
    ASSERT_FALSE(tables->targets().empty()) << what;
    for (const bool shifted : {false, true}) {
      BankBackend bank("banks", sobolBanks(*tables, kSpp, 256), 4, 0x6f7074696d697a65ull, shifted);
      EXPECT_NEAR(run(bank, IntegratorKind::Direct, routes), reference, 0.003 * reference)
          << "shifted " << shifted << " " << what;
      EXPECT_EQ(bank.servedTargets(), tables->targets().size());
    }
  }
}

// Multiple importance sampling where a table draws the BSDF sample: both
// strategies weigh by the material's sampling pdf (BsdfSample::misPdf), so the
// weights sum to 1 at every direction and the estimate is unbiased, while
// the BSDF sample divides by the table's density that drew it. A rough lobe
// under a constant map (light and BSDF pdfs of the same size, so both
// weights matter), every bin forced through a coarse table (whose pdf is
// far from the material's, so a weight or a division by the wrong density
// shows): direct lighting against light sampling alone, which has no BSDF
// strategy and no weights.
TEST(LobeRoutes, MisWeightsSumToOneWhereTablesDrawTheBsdfSample) {
  const Scene scene =
      test::sceneWith({test::unitSphere()}, {material(1.0, 0.0, 0.0)}, test::constantMap(1.0f),
                      {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 12, false});
  LobeTableSettings table;
  table.routing = LobeRouting::Table;
  table.phiCells = 8;  // coarse cells: the table's pdf far from the material's
  const auto run = [&](const std::string &name, IntegratorKind kind) {
    RenderSettings s{12, 12, 1024, kind, 1};
    s.lobeTables = table;
    return meanOf(render(scene, s, *makeBackend(name, 3)));
  };
  const double reference = run("sobol", IntegratorKind::Light);
  EXPECT_NEAR(run("sobol-tabulated", IntegratorKind::Direct), reference, 0.003 * reference);
}

// Measured routes and lobe banks render the same image on one thread and on
// many.
TEST(LobeRoutes, RendersAreEqualForAnyThreadCount) {
  const auto glossy = material(0.8, 0.0, 0.0);
  const Scene scene = test::sceneWith({test::unitSphere()}, {glossy}, test::constantMap(1.0f),
                                      {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40, false});
  RenderSettings s{24, 20, 8, IntegratorKind::Path, 4};
  s.lobeTables.phiCells = 64;
  const auto tables = scene.lobeTables->get(scene.materials, lobeTablesFor(s));
  ASSERT_GT(tables->targets().size(), 0u);
  const auto renderWith = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    BankBackend bank("banks", sobolBanks(*tables, 8), 4);
    return std::pair{render(scene, s, *makeBackend("sobol-tabulated", 9)).pixels,
                     render(scene, s, bank).pixels};
  };
  EXPECT_EQ(renderWith(1), renderWith(4));
}

}  // namespace
}  // namespace nuld
