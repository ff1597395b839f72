#include "renderer/render.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "sampler/diagnostics.h"
#include "sampler/io/round_trip.h"
#include "sampler/resources.h"

namespace nuld {

namespace {

constexpr int kTile = 16;  // tiles of kTile x kTile pixels, one task each

// The domains a path may ask for (one bounce's but under path).
std::uint32_t pathDomains(const RenderSettings &s) {
  return SampleLayout::domains(s.integrator == IntegratorKind::Path ? s.maxDepth : 1);
}

// Renders the tile whose top-left pixel is (x0, y0) into `image`.
void renderTile(const Scene &scene, const RenderSettings &s, SamplerBackend &backend,
                const PerspectiveCamera &camera, const PathIntegrator &integrator, int x0, int y0,
                Image &image, PathCounters &c) {
  constexpr std::size_t kPacket = PathIntegrator::kMaxPaths;
  // Camera rays are traced 16 at a time as one coherent packet: a pixel's
  // samples in chunks of 16, or for spp < 16 the samples of 16 / spp
  // neighbouring pixels of a tile row together. Each pixel still sums its
  // samples in index order, so the image does not depend on the grouping.
  const int groupPixels = int(std::max<std::size_t>(1, kPacket / s.spp));
  std::vector<PixelSamples> samples(groupPixels, PixelSamples(backend, s.spp));
  std::array<Rgb, kPacket> sums;
  std::array<Ray, kPacket> cameraRays;
  std::array<std::optional<SurfaceHit>, kPacket> cameraHits;
  std::array<PixelSamples *, kPacket> pathSamples;
  std::array<std::size_t, kPacket> pathIndices;
  std::array<Rgb, kPacket> radiance;
  const int xEnd = std::min(x0 + kTile, s.width);
  for (int y = y0; y < std::min(y0 + kTile, s.height); ++y)
    for (int gx = x0; gx < xEnd; gx += groupPixels) {
      const int pixels = std::min(groupPixels, xEnd - gx);
      for (int p = 0; p < pixels; ++p) {
        samples[p].startPixel(std::uint64_t(y) * s.width + gx + p);
        sums[p] = {};
      }
      const std::size_t total = std::size_t(pixels) * s.spp;
      for (std::size_t first = 0; first < total; first += kPacket) {
        const std::size_t n = std::min(kPacket, total - first);
        for (std::size_t k = 0; k < n; ++k) {
          const std::size_t p = (first + k) / s.spp, i = (first + k) % s.spp;
          const Point2 jitter = samples[p].primary(SampleLayout::camera, i);
          cameraRays[k] = camera.generateRay({gx + int(p) + jitter.x, y + jitter.y});
        }
        scene.geometry.intersectCoherent(std::span(cameraRays.data(), n),
                                         std::span(cameraHits.data(), n));
        for (std::size_t k = 0; k < n; ++k) {
          pathSamples[k] = &samples[(first + k) / s.spp];
          pathIndices[k] = (first + k) % s.spp;
        }
        integrator.radiance(std::span(cameraRays.data(), n), std::span(cameraHits.data(), n),
                            std::span(pathSamples.data(), n), std::span(pathIndices.data(), n),
                            std::span(radiance.data(), n), c);
        for (std::size_t k = 0; k < n; ++k) sums[(first + k) / s.spp] += radiance[k];
      }
      for (int p = 0; p < pixels; ++p) {
        const Rgb mean = sums[p] / double(s.spp);
        image.at(gx + p, y, 0) = float(mean.r);
        image.at(gx + p, y, 1) = float(mean.g);
        image.at(gx + p, y, 2) = float(mean.b);
      }
    }
}

}  // namespace

ImageAttributes renderAttributes(const std::string &sceneName, const Scene &scene,
                                 const RenderSettings &s, const std::string &backend,
                                 std::uint64_t seed, const RenderStats &stats) {
  const LobeTablesConfig lobes = lobeTablesFor(s);
  return {
      {"nuld:scene", sceneName},
      {"nuld:backend", backend},
      {"nuld:seed", std::to_string(seed)},
      {"nuld:spp", std::to_string(s.spp)},
      {"nuld:integrator", toString(s.integrator)},
      {"nuld:resolution", std::to_string(s.width) + "x" + std::to_string(s.height)},
      {"nuld:max_depth", std::to_string(s.maxDepth)},
      {"nuld:lobe_choice", toString(scene.lobeChoice)},
      {"nuld:env_importance", scene.environment ? toString(scene.environment->weight()) : "none"},
      {"nuld:lobe_mix", formatRoundTrip(lobes.samplingMix)},
      {"nuld:lobe_routes", toString(lobes.settings.routing)},
      {"nuld:lobe_defensive", formatRoundTrip(lobes.settings.defensive)},
      {"nuld:lobe_bounces", std::to_string(lobes.settings.bounces)},
      {"nuld:render_seconds", formatRoundTrip(stats.seconds)},
      {"nuld:setup_seconds", formatRoundTrip(stats.setupSeconds)},
      {"nuld:renderer_revision", std::to_string(kRendererRevision)},
      {"nuld:version", NULD_VERSION}};
}

OverrideNames OverrideNames::options() {
  return {"",
          "--spp",
          "--res",
          "--res-scale",
          "--integrator",
          "--max-depth",
          "--lobe-mix",
          "--lobe-defensive",
          "--lobe-bounces"};
}

OverrideNames OverrideNames::python() {
  return {"render: ",  "spp",      "resolution",     "resolution_scale", "integrator",
          "max_depth", "lobe_mix", "lobe_defensive", "lobe_bounces"};
}

double renderMemoryBytes(const RenderSettings &s) {
  constexpr double kPixelBytes = 2 * 3 * sizeof(float);  // the image and its caller's copy
  // A tile's task renders max(1, 16 / spp) pixels at once (renderTile),
  // each with spp samples of every domain its paths reach and of one context
  // a domain (counted as if every domain were 2D).
  const double samples = std::max<double>(double(s.spp), double(PathIntegrator::kMaxPaths));
  const double threadBytes = samples * double(pathDomains(s)) * 2 * sizeof(Point2);
  const double threads =
      double(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  return double(s.width) * double(s.height) * kPixelBytes + threads * threadBytes;
}

void RenderOverrides::check(const OverrideNames &names) const {
  const auto fail = [&](const std::string &name, const std::string &expected, double got) {
    throw std::invalid_argument(names.prefix + name + ": expected " + expected + " (got " +
                                formatRoundTrip(got) + ")");
  };
  if (spp && *spp == 0) fail(names.spp, "at least 1 sample per pixel", 0);
  if (width && *width < 1) fail(names.resolution, "sides of at least 1 pixel", *width);
  if (height && *height < 1) fail(names.resolution, "sides of at least 1 pixel", *height);
  if (!(resolutionScale > 0 && resolutionScale <= 16))
    fail(names.resolutionScale, "a factor in (0, 16]", resolutionScale);
  if (maxDepth && (*maxDepth < 1 || *maxDepth > kMaxDepthLimit))
    fail(names.maxDepth, "a whole number from 1 to " + std::to_string(kMaxDepthLimit), *maxDepth);
  if (lobeMix && !(*lobeMix >= 0 && *lobeMix <= 1))
    fail(names.lobeMix, "a number in [0, 1]", *lobeMix);
  if (lobeDefensive && !(*lobeDefensive >= 0 && *lobeDefensive <= 1))
    fail(names.lobeDefensive, "a number in [0, 1]", *lobeDefensive);
  if (lobeBounces && (*lobeBounces < 0 || *lobeBounces > kMaxDepthLimit))
    fail(names.lobeBounces,
         "a whole number from 0 (every bounce) to " + std::to_string(kMaxDepthLimit), *lobeBounces);
}

RenderSettings RenderOverrides::appliedTo(RenderSettings s, const OverrideNames &names) const {
  check(names);
  if (spp) s.spp = *spp;
  if (width) {
    // A width alone keeps the scene's aspect (a 3:2 scene at --res 96 is
    // 96x64), as --res-scale does.
    const int sceneWidth = s.width, sceneHeight = s.height;
    s.width = *width;
    s.height =
        height ? *height : std::max(1, int(std::lround(double(*width) * sceneHeight / sceneWidth)));
  } else if (resolutionScale != 1) {
    s.width = std::max(1, int(std::lround(s.width * resolutionScale)));
    s.height = std::max(1, int(std::lround(s.height * resolutionScale)));
  }
  if (integrator) s.integrator = *integrator;
  if (maxDepth) s.maxDepth = *maxDepth;
  if (lobeMix) s.lobeTables.samplingMix = lobeMix;
  if (lobeRouting) s.lobeTables.routing = *lobeRouting;
  if (lobeDefensive) s.lobeTables.defensive = *lobeDefensive;
  if (lobeBounces) s.lobeTables.bounces = *lobeBounces;
  requireMemory(renderMemoryBytes(s),
                names.prefix + names.resolution + ": a " + std::to_string(s.width) + " x " +
                    std::to_string(s.height) + " render at " + std::to_string(s.spp) + " spp");
  return s;
}

void RenderOverrides::checkApplicable(const RenderSettings &applied,
                                      const OverrideNames &names) const {
  if (maxDepth && applied.integrator != IntegratorKind::Path)
    throw std::invalid_argument(names.prefix + names.maxDepth + " applies to " + names.integrator +
                                " path only (" + toString(applied.integrator) +
                                " traces one bounce)");
}

LobeTablesConfig lobeTablesFor(const RenderSettings &s) {
  LobeTablesConfig out;
  out.settings = s.lobeTables;
  out.samplingMix =
      s.lobeTables.samplingMix.value_or(s.integrator == IntegratorKind::Bsdf ? 0.0 : 1.0);
  out.underMis = s.integrator == IntegratorKind::Direct;
  return out;
}

Image render(const Scene &scene, const RenderSettings &s, SamplerBackend &backend,
             RenderStats *stats, const RenderProgress &progress, std::vector<RecordedRay> *rays) {
  if (s.width <= 0 || s.height <= 0) throw std::invalid_argument("render: resolution must be > 0");
  if (s.spp == 0) throw std::invalid_argument("render: spp must be at least 1");
  if (scene.materials.size() != scene.geometry.meshes().size())
    throw std::invalid_argument("render: every mesh needs a material");
  if (s.integrator == IntegratorKind::Bsdf && !scene.lights.punctual.empty())
    warning("render: the bsdf integrator cannot meet the scene's " +
            std::to_string(scene.lights.punctual.size()) +
            " point, spot or directional light(s): no BSDF sample reaches a light of no extent, "
            "so they light nothing in this image");
  const auto setupStart = std::chrono::steady_clock::now();
  SamplingTargets targets;
  targets.width = std::uint32_t(s.width), targets.height = std::uint32_t(s.height);
  targets.domains = pathDomains(s);
  targets.integrator = toString(s.integrator);
  const EnvironmentLight *light = sampledLight(scene, s.integrator);
  targets.light = light ? light->target() : nullptr;
  std::shared_ptr<const LobeTables> lobes;
  if (backend.samplesLobes() && s.integrator != IntegratorKind::Light) {
    lobes = scene.lobeTables
                ? scene.lobeTables->get(scene.materials, lobeTablesFor(s))
                : std::make_shared<const LobeTables>(scene.materials, lobeTablesFor(s));
    targets.lobes = lobes->targets();
    if (stats) {
      stats->lobeBins = lobes->routes().size();
      stats->lobeBinsTabulated = targets.lobes.size();
    }
  }
  backend.prepare(s.spp, targets);
  if (stats) stats->setsMadeSeconds = backend.report().setsMadeSeconds;

  const auto start = std::chrono::steady_clock::now();
  const PerspectiveCamera camera(scene.camera, s.width, s.height);
  const PathIntegrator integrator(scene, s.integrator, s.maxDepth, lobes.get(), s.rouletteDepth);
  Image image{s.width, s.height, 3, std::vector<float>(std::size_t(s.width) * s.height * 3)};

  const int tilesX = (s.width + kTile - 1) / kTile, tilesY = (s.height + kTile - 1) / kTile;
  const std::size_t tileCount = std::size_t(tilesX) * tilesY;
  tbb::enumerable_thread_specific<PathCounters> counters;
  tbb::enumerable_thread_specific<std::vector<RecordedRay>> recorded;
  std::atomic<std::size_t> done{0};
  std::mutex progressMutex;

  const auto renderTiles = [&](std::size_t first, std::size_t end) {
    tbb::parallel_for(first, end, [&](std::size_t t) {
      PathCounters &c = counters.local();
      if (rays) c.recorder = &recorded.local();
      renderTile(scene, s, backend, camera, integrator, int(t % tilesX) * kTile,
                 int(t / tilesX) * kTile, image, c);
      const std::size_t finished = ++done;
      if (progress) {
        std::lock_guard lock(progressMutex);
        progress(finished, tileCount);
      }
    });
  };
  if (const std::size_t perStage = backend.tilesPerStage(); perStage == 0) {
    renderTiles(0, tileCount);
  } else {
    std::vector<std::uint64_t> pixels;
    for (std::size_t first = 0; first < tileCount; first += perStage) {
      const std::size_t end = std::min(tileCount, first + perStage);
      pixels.clear();
      for (std::size_t t = first; t < end; ++t) {
        const int x0 = int(t % tilesX) * kTile, y0 = int(t / tilesX) * kTile;
        for (int y = y0; y < std::min(y0 + kTile, s.height); ++y)
          for (int x = x0; x < std::min(x0 + kTile, s.width); ++x)
            pixels.push_back(std::uint64_t(y) * s.width + x);
      }
      backend.stage(pixels);
      renderTiles(first, end);
    }
  }

  if (rays)
    for (auto &part : recorded) rays->insert(rays->end(), part.begin(), part.end());
  if (stats) {
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats->setupSeconds = std::chrono::duration<double>(start - setupStart).count();
    stats->rays = stats->rejectedSamples = stats->classicFallbacks = 0;
    for (const PathCounters &c : counters) {
      stats->rays += c.rays;
      stats->rejectedSamples += c.rejected;
      stats->classicFallbacks += c.classicFallbacks;
    }
  }
  return image;
}

}  // namespace nuld
