// Renderer benchmarks (Google Benchmark; not timed tests):
//  - PathTracer/SCENE/spp:N: the whole renderer at 512^2 and N spp per
//    iteration, reported as traced rays per second;
//  - Backend/SCENE/BACKEND: a 16-spp path render at the scene's resolution
//    with sobol and with sobol-tabulated side by side (the lobe tables are
//    built before timing: a scene builds them once);
//  - BM_MaterialSample, BM_LobeRouteSample, BM_LobeRouteFromTablePoint: one
//    BSDF sample through the material's own sampler and through a tabulated
//    route (table inverse CDF and the defensive split; or from a point that
//    already follows the table, as lobe banks deal them), at the dragon's
//    material;
//  - BM_NeuralModelLoad, BM_NeuralBackendMake: reading the shipped model, and
//    a whole `neural` backend made from it (per render and repeat);
//  - BM_NeuralLobeBank/N: one lobe table's bank of 16 sets from the shipped
//    model (the neural backend's inference per table);
//  - EmbreeRaw/SCENE/spp:N: the same rays, recorded from one such render,
//    replayed through rtcIntersect1 alone with the same TBB parallelism.
// Their ratio (renderer rays/s over raw rays/s) measures the renderer's own
// cost per ray; tools/experiments/renderer_speed.md has it measured, and
// what raising it would take. N is 4 (quick, per-pixel costs weigh most) and
// the scene file's own spp (64 for lte-orb: what `nuld render` runs; its
// recording holds every ray of one render in memory, tens of millions; its
// size is in tools/experiments/README.md's renderer speed entry). Needs the
// assets (NULD_ASSETS or ../shared/assets); the default scene is benchmarked
// too, which needs none.

#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <filesystem>
#include <memory>

#include "backends/backend_registry.h"
#include "backends/neural_backend.h"
#include "materials/disney.h"
#include "materials/disney_target.h"
#include "renderer/lobe_tables.h"
#include "renderer/render.h"
#include "scenes/scene_file.h"
#include "tests/bench/bench_points.h"

namespace nuld {
namespace {

struct Fixture {
  LoadedScene scene;
  std::map<std::size_t, std::vector<RecordedRay>> rays;  // by spp; one recording at a time
};

Fixture &fixture(const std::string &name) {
  static std::map<std::string, std::unique_ptr<Fixture>> cache;
  auto &slot = cache[name];
  if (!slot) {
    const std::string path =
        name == "default" ? name : std::string(NULD_SOURCE_DIR) + "/scenes/" + name + ".json";
    slot = std::make_unique<Fixture>(Fixture{loadScene(path, resolveAssetRoot("")), {}});
  }
  return *slot;
}

// spp 0: the scene file's own.
RenderSettings benchSettings(const LoadedScene &s, std::size_t spp) {
  RenderSettings r = s.settings;
  r.width = r.height = 512;
  if (spp > 0) r.spp = spp;
  return r;
}

void PathTracer(benchmark::State &state, const std::string &name, std::size_t spp) {
  Fixture &f = fixture(name);
  const RenderSettings settings = benchSettings(f.scene, spp);
  std::uint64_t rays = 0;
  for (auto _ : state) {
    auto backend = makeBackend("sobol", 0);
    RenderStats stats;
    benchmark::DoNotOptimize(render(f.scene.scene, settings, *backend, &stats));
    rays += stats.rays;
  }
  state.counters["rays_per_second"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
}

void EmbreeRaw(benchmark::State &state, const std::string &name, std::size_t spp) {
  Fixture &f = fixture(name);
  const RenderSettings settings = benchSettings(f.scene, spp);
  std::vector<RecordedRay> &recorded = f.rays[settings.spp];
  if (recorded.empty()) {
    f.rays.clear();  // only one recording in memory
    auto backend = makeBackend("sobol", 0);
    render(f.scene.scene, settings, *backend, nullptr, {}, &f.rays[settings.spp]);
  }
  const std::vector<RecordedRay> &rec = f.rays[settings.spp];
  const EmbreeScene &geometry = f.scene.scene.geometry;
  std::uint64_t rays = 0;
  for (auto _ : state) {
    std::atomic<std::uint64_t> hits{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rec.size(), 4096), [&](auto range) {
      std::uint64_t local = 0;
      for (std::size_t i = range.begin(); i < range.end(); ++i)
        local += std::isfinite(geometry.rawIntersect(rec[i].origin, rec[i].direction));
      hits += local;
    });
    benchmark::DoNotOptimize(hits.load());
    rays += rec.size();
  }
  state.counters["rays_per_second"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
}

void Backend(benchmark::State &state, const std::string &name, const std::string &backendName) {
  Fixture &f = fixture(name);
  RenderSettings settings = f.scene.settings;
  settings.spp = 16;
  settings.integrator = IntegratorKind::Path;
  {  // the scene's tables, built once as every render of the scene would
    auto backend = makeBackend(backendName, 0);
    if (backend->samplesLobes())
      f.scene.scene.lobeTables->get(f.scene.scene.materials, lobeTablesFor(settings));
  }
  for (auto _ : state) {
    auto backend = makeBackend(backendName, 0);
    benchmark::DoNotOptimize(render(f.scene.scene, settings, *backend));
  }
}

// The dragon's material (scenes/dragon.json) at a 45-degree view.
DisneyParams dragonMaterial() {
  DisneyParams p;
  p.baseColor = {0.35, 0.65, 0.45};
  p.subsurface = 1;
  p.roughness = 0.45;
  p.specular = 0.5;
  p.sheen = 0.3;
  return p;
}
const Vec3 kWo{0.7071067811865476, 0, 0.7071067811865476};

using bench::uniformPoints;

void BM_MaterialSample(benchmark::State &state) {
  const DisneyBrdf brdf(dragonMaterial());
  const auto us = uniformPoints(4096);
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(brdf.sample(kWo, us[(k + 7) & 4095].x, us[k & 4095]));
    ++k;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_MaterialSample);

// The dragon's material with its lobe tables under MIS (mix 1), every bin
// through its table.
struct DragonTables {
  explicit DragonTables(double defensive = LobeTableSettings{}.defensive)
      : brdf(std::make_shared<const DisneyBrdf>(dragonMaterial())), tables({brdf}, [&] {
          LobeTableSettings s;
          s.samplingMix = 1.0;
          s.routing = LobeRouting::Table;
          s.defensive = defensive;
          return s;
        }()) {}
  LobeFrame frame() const { return *tables.frame(brdf.get(), kWo); }

  std::shared_ptr<const DisneyBrdf> brdf;
  LobeTables tables;
};

// Arg: the defensive share in percent. From the table's primary point (its
// CDF map's), as sobol-tabulated's are.
void BM_LobeRouteSample(benchmark::State &state) {
  const DragonTables dragon(double(state.range(0)) / 100);
  const LobeFrame lobe = dragon.frame();
  const auto us = uniformPoints(4096);
  std::size_t k = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(sampleRoute(*dragon.brdf, kWo, lobe, {us[k++ & 4095]}, 0.5));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_LobeRouteSample)->Arg(0)->Arg(10);

// The same from points that already follow the table, as a lobe bank deals
// them (arg: the defensive share in percent; with one, each point is
// pulled back to the table's primary space first).
void BM_LobeRouteFromTablePoint(benchmark::State &state) {
  const DragonTables dragon(double(state.range(0)) / 100);
  const LobeFrame lobe = dragon.frame();
  std::vector<Point2> xs;
  for (const Point2 u : uniformPoints(4096)) xs.push_back(lobe.table->invert(u).x);
  std::size_t k = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(sampleRoute(*dragon.brdf, kWo, lobe, {xs[k++ & 4095], true}, 0.5));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_LobeRouteFromTablePoint)->Arg(0)->Arg(10);

// What making a `neural` backend costs before it renders, which every
// repeat of a study and every `nuld render` pays: reading the shipped model
// (its file parsed and checksummed; the network waits for a bank to make)
// and the whole backend made from it.
void BM_NeuralModelLoad(benchmark::State &state) {
  registerMaterialTargets();
  const std::string path = shippedLobeModel();
  for (auto _ : state)
    benchmark::DoNotOptimize(
        NeuralGenerator::load(path, NeuralGenerator::NetworkLoad::OnFirstUse).fileChecksum());
}
BENCHMARK(BM_NeuralModelLoad)->Unit(benchmark::kMicrosecond);
void BM_NeuralBackendMake(benchmark::State &state) {
  registerMaterialTargets();
  std::uint64_t seed = 0;
  for (auto _ : state) benchmark::DoNotOptimize(makeBackend("neural", ++seed));
}
BENCHMARK(BM_NeuralBackendMake)->Unit(benchmark::kMicrosecond);

// One lobe table's bank from the shipped model, as the neural backend makes
// it per table and render (16 sets of N = spp points, the renderer's table
// given): the inference cost of a `neural` render is this times the scene's
// serving tables.
void BM_NeuralLobeBank(benchmark::State &state) {
  registerMaterialTargets();
  const DragonTables dragon;
  const Target *table = dragon.tables.targets().front();
  const NeuralGenerator model = NeuralGenerator::load(shippedLobeModel());
  const auto gamma = disneyFamilyGamma(model.family().spec(), table->spec());
  if (!gamma) {
    state.SkipWithError("the shipped model does not serve the table");
    return;
  }
  const std::size_t n = std::size_t(state.range(0));
  std::uint64_t seed = 0;
  for (auto _ : state) benchmark::DoNotOptimize(model.generateSets(16, ++seed, *gamma, n, table));
  state.SetItemsProcessed(state.iterations() * 16);
}
BENCHMARK(BM_NeuralLobeBank)->Arg(16)->Arg(64)->Unit(benchmark::kMillisecond);

bool haveAssets() {
  return std::filesystem::exists(std::filesystem::path(resolveAssetRoot("")) / "lte_orb");
}

const bool registered = [] {
  std::vector<std::string> scenes = {"default"};
  if (haveAssets()) scenes.push_back("lte-orb");
  for (const std::string &s : scenes)
    for (std::size_t spp : {std::size_t(4), std::size_t(0)}) {
      const std::string suffix =
          "/" + s + "/spp:" + (spp ? std::to_string(spp) : std::string("scene"));
      // Each pair back to back, so a recording is made once and dropped after.
      benchmark::RegisterBenchmark(("PathTracer" + suffix).c_str(), PathTracer, s, spp)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark(("EmbreeRaw" + suffix).c_str(), EmbreeRaw, s, spp)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  if (haveAssets())
    for (const char *b : {"sobol", "sobol-tabulated"})
      benchmark::RegisterBenchmark((std::string("Backend/dragon/") + b).c_str(), Backend, "dragon",
                                   b)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
  return true;
}();

}  // namespace
}  // namespace nuld

BENCHMARK_MAIN();
