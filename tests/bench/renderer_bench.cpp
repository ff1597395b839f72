// Renderer benchmarks (Google Benchmark; not timed tests):
//  - PathTracer/lte-orb: the whole renderer on lte-orb at 512^2, 4 spp per
//    iteration, reported as traced rays per second;
//  - EmbreeRaw/lte-orb: the same rays, recorded from one render, replayed
//    through rtcIntersect1 alone with the same TBB parallelism.
// Their ratio (renderer rays/s over raw rays/s) is what the renderer issue
// asks for (target >= 0.5). Needs the assets (NULD_ASSETS or ../shared/assets);
// the default scene is benchmarked too, which needs none.

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
  std::vector<RecordedRay> rays;
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

RenderSettings benchSettings(const LoadedScene &s) {
  RenderSettings r = s.settings;
  r.width = r.height = 512;
  r.spp = 4;
  return r;
}

void PathTracer(benchmark::State &state, const std::string &name) {
  Fixture &f = fixture(name);
  const RenderSettings settings = benchSettings(f.scene);
  std::uint64_t rays = 0;
  for (auto _ : state) {
    auto backend = makeBackend("sobol", 0);
    RenderStats stats;
    benchmark::DoNotOptimize(render(f.scene.scene, settings, *backend, &stats));
    rays += stats.rays;
  }
  state.counters["rays_per_second"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
}

void EmbreeRaw(benchmark::State &state, const std::string &name) {
  Fixture &f = fixture(name);
  if (f.rays.empty()) {
    auto backend = makeBackend("sobol", 0);
    render(f.scene.scene, benchSettings(f.scene), *backend, nullptr, {}, &f.rays);
  }
  const EmbreeScene &geometry = f.scene.scene.geometry;
  std::uint64_t rays = 0;
  for (auto _ : state) {
    std::atomic<std::uint64_t> hits{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, f.rays.size(), 4096), [&](auto range) {
      std::uint64_t local = 0;
      for (std::size_t i = range.begin(); i < range.end(); ++i)
        local += std::isfinite(geometry.rawIntersect(f.rays[i].origin, f.rays[i].direction));
      hits += local;
    });
    benchmark::DoNotOptimize(hits.load());
    rays += f.rays.size();
  }
  state.counters["rays_per_second"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
}

bool haveAssets() {
  return std::filesystem::exists(std::filesystem::path(resolveAssetRoot("")) / "lte_orb");
}

const bool registered = [] {
  std::vector<std::string> scenes = {"default"};
  if (haveAssets()) scenes.push_back("lte-orb");
  for (const std::string &s : scenes) {
    benchmark::RegisterBenchmark(("PathTracer/" + s).c_str(), PathTracer, s)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    benchmark::RegisterBenchmark(("EmbreeRaw/" + s).c_str(), EmbreeRaw, s)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  return true;
}();

}  // namespace
}  // namespace nuld

BENCHMARK_MAIN();
