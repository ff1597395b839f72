// Renderer benchmarks (Google Benchmark; not timed tests):
//  - PathTracer/SCENE/spp:N: the whole renderer at 512^2 and N spp per
//    iteration, reported as traced rays per second;
//  - EmbreeRaw/SCENE/spp:N: the same rays, recorded from one such render,
//    replayed through rtcIntersect1 alone with the same TBB parallelism.
// Their ratio (renderer rays/s over raw rays/s) is what the renderer issue
// asks for (target >= 0.5). N is 4 (quick, per-pixel costs weigh most) and
// the scene file's own spp (64 for lte-orb: what `nuld render` runs; its
// recording holds 42M rays, about 1 GB). Needs the assets (NULD_ASSETS or
// ../shared/assets); the default scene is benchmarked too, which needs none.

#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <filesystem>
#include <memory>

#include "renderer/render.h"
#include "scenes/scene_file.h"

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
  return true;
}();

}  // namespace
}  // namespace nuld

BENCHMARK_MAIN();
