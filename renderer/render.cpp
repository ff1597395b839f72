#include "renderer/render.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>

namespace nuld {

Image render(const Scene &scene, const RenderSettings &s, SamplerBackend &backend,
             RenderStats *stats, const RenderProgress &progress, std::vector<RecordedRay> *rays) {
  if (s.width <= 0 || s.height <= 0) throw std::invalid_argument("render: resolution must be > 0");
  if (s.spp == 0) throw std::invalid_argument("render: spp must be at least 1");
  if (scene.materials.size() != scene.geometry.meshes().size())
    throw std::invalid_argument("render: every mesh needs a material");
  const GridTarget *lightTarget = scene.environment ? scene.environment->target() : nullptr;
  backend.prepare(s.spp, lightTarget);

  const auto start = std::chrono::steady_clock::now();
  const PerspectiveCamera camera(scene.camera, s.width, s.height);
  const PathIntegrator integrator(scene, s.integrator, s.maxDepth);
  Image image{s.width, s.height, 3, std::vector<float>(std::size_t(s.width) * s.height * 3)};

  constexpr int tile = 16;
  const int tilesX = (s.width + tile - 1) / tile, tilesY = (s.height + tile - 1) / tile;
  const std::size_t tileCount = std::size_t(tilesX) * tilesY;
  tbb::enumerable_thread_specific<PathCounters> counters;
  tbb::enumerable_thread_specific<std::vector<RecordedRay>> recorded;
  std::atomic<std::size_t> done{0};
  std::mutex progressMutex;

  tbb::parallel_for(std::size_t(0), tileCount, [&](std::size_t t) {
    PathCounters &c = counters.local();
    if (rays) c.recorder = &recorded.local();
    PixelSamples samples(backend, s.spp);
    const int x0 = int(t % tilesX) * tile, y0 = int(t / tilesX) * tile;
    for (int y = y0; y < std::min(y0 + tile, s.height); ++y)
      for (int x = x0; x < std::min(x0 + tile, s.width); ++x) {
        samples.startPixel(std::uint64_t(y) * s.width + x);
        Rgb sum;
        for (std::size_t i = 0; i < s.spp; ++i) {
          const Point2 jitter = samples.primary(SamplePairs::camera, i);
          const Ray ray = camera.generateRay({x + jitter.x, y + jitter.y});
          sum += integrator.radiance(ray, samples, i, c);
        }
        const Rgb mean = sum / double(s.spp);
        image.at(x, y, 0) = float(mean.r);
        image.at(x, y, 1) = float(mean.g);
        image.at(x, y, 2) = float(mean.b);
      }
    const std::size_t finished = ++done;
    if (progress) {
      std::lock_guard lock(progressMutex);
      progress(finished, tileCount);
    }
  });

  if (rays)
    for (auto &part : recorded) rays->insert(rays->end(), part.begin(), part.end());
  if (stats) {
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats->rays = stats->rejectedSamples = 0;
    for (const PathCounters &c : counters) {
      stats->rays += c.rays;
      stats->rejectedSamples += c.rejected;
    }
  }
  return image;
}

}  // namespace nuld
