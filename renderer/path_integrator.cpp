#include "renderer/path_integrator.h"

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "materials/frame.h"
#include "materials/sphere_map.h"

namespace nuld {

const EnvironmentLight *sampledLight(const Scene &scene, IntegratorKind kind) {
  if (!scene.environment) return nullptr;
  return kind == IntegratorKind::Light ? &scene.environment->uncompensated() : &*scene.environment;
}

PathIntegrator::PathIntegrator(const Scene &scene, IntegratorKind kind, int maxDepth,
                               const LobeTables *lobes, int rouletteDepth)
    : scene_(scene),
      light_(sampledLight(scene, kind)),
      lobes_(lobes),
      maxDepth_(kind == IntegratorKind::Path ? maxDepth : 1),
      rouletteDepth_(rouletteDepth),
      strategies_(Strategies::of(kind)),
      environmentChoice_(scene.lights.choice && light_
                             ? scene.lights.choice->probability(scene.lights.count())
                             : 1.0) {
  if (maxDepth < 1) throw std::invalid_argument("max depth must be at least 1");
  if (rouletteDepth < 1) throw std::invalid_argument("roulette depth must be at least 1");
}

PathIntegrator::Strategies PathIntegrator::Strategies::of(IntegratorKind kind) {
  return {kind != IntegratorKind::Bsdf, kind != IntegratorKind::Light};
}

double PathIntegrator::misWeight(double pdf, double otherPdf) const {
  return strategies_.light && strategies_.bsdf ? powerHeuristic(pdf, otherPdf) : 1.0;
}

namespace {

// The shading frame at a hit. For a material that reflects only, it is
// turned to the side the path arrives from (every such material is
// two-sided), and a shading normal that faces away from wo is replaced by the
// geometric one, which always faces wo. A transmitting material needs to know
// which side is outside: its frame keeps the outward normal (the vertex
// normals' side, embree_scene.cpp), again the geometric one where the shading
// normal puts wo on the other side.
struct Shading {
  Frame frame;
  Vec3 origin;   // where rays toward wo's side leave the surface (shadingAt)
  Vec3 through;  // where refracted rays leave it, on the other side (transmitting materials)
  // Where a ray toward local direction wi leaves, given the local view wo:
  // only a refraction (wi on the other side of the shading normal from wo)
  // crosses, so a reflected direction between the flat triangle and the
  // shading plane keeps the terminator policy below.
  Vec3 leave(Vec3 wo, Vec3 wi) const { return wo.z * wi.z < 0 ? through : origin; }
};

// Where rays leave the surface: on wo's side, or for a refracted direction
// offset to the other side. The terminator policy: the shading normal decides
// which directions are sampled and the BSDF is evaluated in its frame, and
// rays start at the shading position (the smooth surface the vertex normals
// describe; embree_scene.h) where that lies on wo's side of the flat
// triangle, offset to that side. So a direction between the flat triangle's
// plane and the shading plane is traced, not dropped: on a convex
// smooth-shaded patch it escapes as it would the smooth surface, and a white
// furnace returns the albedo (render_test.cpp); where it does hit the mesh,
// that hit shadows it or continues the path like any other.
Shading shadingAt(const SurfaceHit &hit, Vec3 wo, bool transmits = false) {
  Vec3 ng = hit.geometricNormal, ns = hit.shadingNormal;
  const bool outside = dot(wo, ng) >= 0;
  if (!outside) ng = -ng, ns = -ns;
  if (dot(wo, ns) <= 0) ns = ng;
  const Vec3 base =
      dot(hit.shadingOffset, ng) > 0 ? hit.position + hit.shadingOffset : hit.position;
  return {Frame::fromNormal(transmits && !outside ? -ns : ns), offsetRayOrigin(base, ng, ng),
          offsetRayOrigin(hit.position, ng, -ng)};
}

void record(PathCounters &c, const Ray &r) {
  ++c.rays;
  if (c.recorder)
    c.recorder->push_back({{float(r.origin.x), float(r.origin.y), float(r.origin.z)},
                           {float(r.direction.x), float(r.direction.y), float(r.direction.z)}});
}

}  // namespace

Vec3 shadingLocal(const SurfaceHit &hit, Vec3 wo) { return shadingAt(hit, wo).frame.toLocal(wo); }

// One path's state between bounces.
struct PathIntegrator::PathState {
  Rgb L, beta{1, 1, 1};
  Ray ray;
  // The material's sampling pdf at the last BSDF sample's direction, which
  // weighs what the ray finds by MIS (BsdfSample::misPdf); none for the
  // camera ray.
  double lastBsdfPdf = 0;
  bool cameraRay = true;
  bool alive = true;
  PixelSamples *samples = nullptr;
  std::size_t index = 0;
  EnvironmentLight::Lookup escape;  // the map's cell for `ray`, if it escapes
  // At the current hit: its material, `local` where a texture makes it
  // for this hit (Scene::textured).
  const Bsdf *bsdf = nullptr;
  std::optional<DisneyBrdf> local;
  Shading sh;
  Vec3 wo;
  // The BSDF strategy of this sample at the hit: the tabulated lobe `lobe`
  // with the backend's point for its table, `lobePoint`, or (lobe.table
  // null) the material's own sample().
  LobeFrame lobe;
  RoutePoint lobePoint;
};

namespace {

// The light samples of the live paths at bounce `depth` into ls[k], drawn
// together: their reads of the light's tables overlap (the batch forms of the
// light give the same values as its one-point forms). At 4 spp a packet holds
// four pixels, so this batches more than one pixel's samples could.
void lightSamples(const EnvironmentLight &light, std::span<PathIntegrator::PathState> paths,
                  int depth, std::span<const bool> chosen,
                  std::span<std::optional<LightSample>> ls) {
  const std::uint32_t domain = SampleLayout::light(depth);
  constexpr std::size_t kMax = PathIntegrator::kMaxPaths;
  Point2 target[kMax], primary[kMax];
  std::size_t targetOf[kMax], primaryOf[kMax], nt = 0, np = 0;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    if (!paths[k].alive || !chosen[k]) continue;
    PixelSamples &s = *paths[k].samples;
    if (const Point2 *x = s.distributed(*light.target(), domain, paths[k].index)) {
      target[nt] = *x, targetOf[nt++] = k;
    } else {
      primary[np] = s.primary(domain, paths[k].index), primaryOf[np++] = k;
    }
  }
  std::optional<LightSample> out[kMax];
  light.sampleTarget(std::span(target, nt), std::span(out, nt));
  for (std::size_t q = 0; q < nt; ++q) ls[targetOf[q]] = out[q];
  light.sample(std::span(primary, np), std::span(out, np));
  for (std::size_t q = 0; q < np; ++q) ls[primaryOf[q]] = out[q];
}

}  // namespace

void PathIntegrator::addEmitted(PathState &p, std::size_t light, Rgb Le) const {
  const SceneLights &lights = scene_.lights;
  const double w =
      p.cameraRay
          ? 1.0
          : misWeight(p.lastBsdfPdf, lights.choice->probability(light) *
                                         lights.light(light).pdf(p.ray.origin, p.ray.direction));
  p.L += w * p.beta * Le;
}

bool PathIntegrator::arrive(std::span<PathState> path,
                            std::span<const std::optional<SurfaceHit>> hit, int depth) const {
  const std::size_t n = path.size();
  // Rays that escaped, paths that end here, and the shading at each hit.
  bool any = false;
  const SceneLights &lights = scene_.lights;
  for (std::size_t k = 0; k < n; ++k) {
    PathState &p = path[k];
    if (!p.alive) continue;
    // A ray that meets a rectangle or sphere light before any surface ends
    // there, adding its radiance (weighed against the light's own sampling
    // when a BSDF sample drew the ray).
    if (!lights.shapes.empty()) {
      const double tSurface = hit[k] ? hit[k]->t : std::numeric_limits<double>::infinity();
      std::size_t nearest = lights.shapes.size();
      AreaLight::Hit at{tSurface, {}};
      for (std::size_t i = 0; i < lights.shapes.size(); ++i)
        if (const auto h = lights.shapes[i].intersect(p.ray.origin, p.ray.direction);
            h && h->distance < at.distance)
          at = *h, nearest = i;
      if (nearest < lights.shapes.size()) {
        addEmitted(p, nearest, lights.shapes[nearest].emitted(at.normal, p.ray.direction));
        p.alive = false;
        continue;
      }
    }
    if (!hit[k]) {
      if (light_) {
        double lightPdf;
        const Rgb Le =
            light_->radiance(depth > 0 ? p.escape : light_->find(p.ray.direction), lightPdf);
        const double w =
            p.cameraRay ? 1.0 : misWeight(p.lastBsdfPdf, environmentChoice_ * lightPdf);
        p.L += w * p.beta * Le;
      }
      p.alive = false;
      continue;
    }
    // An emitting mesh's triangle adds its radiance and still reflects.
    if (const std::uint32_t first = hit[k]->mesh < lights.meshFirst.size()
                                        ? lights.meshFirst[hit[k]->mesh]
                                        : SceneLights::kNone;
        first != SceneLights::kNone) {
      const std::size_t t = first + hit[k]->triangle;
      addEmitted(p, lights.shapes.size() + t, lights.triangles[t].emittedTowards(p.ray.direction));
    }
    if (depth >= maxDepth_) {
      p.alive = false;
      continue;
    }
    // Russian roulette, on arriving at a hit (from the `rouletteDepth_`-th
    // on, 0-based) and before its next-event estimation: cutting a path
    // after its BSDF sample instead (pbrt-v4's place) also cuts the MIS
    // half of the previous hit's direct light. Survival sqrt(max beta)
    // (Cycles' rule), not max beta: it lowered the pixel variance for about
    // the same time (measured in tools/experiments/path_noise.md).
    if (depth >= rouletteDepth_ && p.beta.maxComponent() < 1) {
      const double q = std::max(0.0, 1 - std::sqrt(p.beta.maxComponent()));
      if (p.samples->number(SampleLayout::roulette(depth), p.index) < q) {
        p.alive = false;
        continue;
      }
      p.beta = p.beta / (1 - q);
    }
    const std::uint32_t mesh = hit[k]->mesh;
    if (mesh < scene_.textured.size() && scene_.textured[mesh]) {
      const TexturedDisney &t = *scene_.textured[mesh];
      p.bsdf = &p.local.emplace(t.at(hit[k]->uv), t.lobes);
    } else {
      p.bsdf = scene_.materials[mesh].get();
    }
    p.sh = shadingAt(*hit[k], -p.ray.direction, p.bsdf->transmits());
    p.wo = p.sh.frame.toLocal(-p.ray.direction);
    p.alive = p.bsdf->transmits() ? p.wo.z != 0 : p.wo.z > 0;
    any = any || p.alive;
  }
  return any;
}

void PathIntegrator::chooseBsdfStrategies(std::span<PathState> path, int depth,
                                          PathCounters &counters) const {
  const std::size_t n = path.size();
  // The BSDF strategy of each sample: the table's route when the backend
  // serves the shading point's table, else the material's own sample().
  // (The light sample's MIS weight takes the material's pdf whichever
  // strategy this picks.)
  for (std::size_t k = 0; k < n; ++k) {
    PathState &p = path[k];
    p.lobe = {};
    if (!p.alive || !lobes_ ||
        (lobes_->settings().bounces > 0 && depth >= lobes_->settings().bounces))
      continue;
    const auto frame = lobes_->frame(p.bsdf, p.wo);
    if (!frame) continue;
    if (p.samples->tablePoint(*frame->table, SampleLayout::bsdf(depth), p.index, p.lobePoint)) {
      p.lobe = *frame;
    } else if (depth == 0) {
      ++counters.classicFallbacks;
    }
  }
}

void PathIntegrator::addLightSamples(std::span<PathState> path, int depth,
                                     PathCounters &counters) const {
  if (!strategies_.light) return;
  const std::size_t n = path.size();
  const SceneLights &lights = scene_.lights;
  const bool environment = light_ && light_->target();
  if (!environment && lights.empty()) return;
  // Which light each path samples: the environment alone in a scene without
  // emitters; else one light chosen by power with the light-choice number.
  std::array<bool, kMaxPaths> chosesEnvironment;
  std::array<double, kMaxPaths> choice;
  std::array<std::optional<AreaLightSample>, kMaxPaths> area;
  std::array<std::size_t, kMaxPaths> areaIndex;
  chosesEnvironment.fill(environment);
  choice.fill(1.0);
  // A material of delta lobes alone (smooth glass) has nothing to meet a
  // light sample with: no sample, no shadow ray.
  std::array<bool, kMaxPaths> samples;
  for (std::size_t k = 0; k < n; ++k) {
    samples[k] = path[k].alive && !path[k].bsdf->onlyDelta();
    chosesEnvironment[k] = chosesEnvironment[k] && samples[k];
  }
  if (lights.choice) {
    for (std::size_t k = 0; k < n; ++k) {
      PathState &p = path[k];
      if (!samples[k]) continue;
      const auto c =
          lights.choice->choose(p.samples->number(SampleLayout::lightChoice(depth), p.index));
      choice[k] = c.probability;
      chosesEnvironment[k] = c.index == lights.count();
      if (chosesEnvironment[k]) continue;
      areaIndex[k] = c.index;
      // A punctual light leaves the light domain undrawn: no dimension
      // shifts, so every light keeps the same layout.
      area[k] = lights.sample(c.index, p.sh.origin,
                              c.index < lights.areaCount()
                                  ? p.samples->primary(SampleLayout::light(depth), p.index)
                                  : Point2{});
    }
  }
  std::array<std::optional<LightSample>, kMaxPaths> ls;
  if (environment) lightSamples(*light_, path, depth, chosesEnvironment, ls);
  for (std::size_t k = 0; k < n; ++k) {
    PathState &p = path[k];
    if (!samples[k]) continue;
    Vec3 wiWorld;
    Rgb radiance;
    double pdf, tMax = std::numeric_limits<double>::infinity();
    if (chosesEnvironment[k]) {
      if (!ls[k]) continue;
      wiWorld = ls[k]->wi, radiance = ls[k]->radiance, pdf = ls[k]->pdf;
    } else {
      if (!area[k] || area[k]->radiance.isBlack()) continue;
      wiWorld = area[k]->wi, radiance = area[k]->radiance, pdf = area[k]->pdf;
      // Up to just before the light: an emitting mesh is in the geometry.
      tMax = area[k]->distance * (1 - 1e-4);
    }
    pdf *= choice[k];
    const Vec3 wi = p.sh.frame.toLocal(wiWorld);
    // Below the shading hemisphere f = 0, unless the material transmits.
    if (!(wi.z > 0) && !(wi.z < 0 && p.bsdf->transmits())) continue;
    // Visibility before the BSDF: an occluded sample then costs no eval.
    const Ray shadow{p.sh.leave(p.wo, wi), wiWorld, tMax};
    record(counters, shadow);
    if (scene_.geometry.occluded(shadow) ||
        shadowedByShapes(shadow, chosesEnvironment[k] ? lights.shapes.size() : areaIndex[k]))
      continue;
    // Alone, the light's weight is 1 and the material's pdf unused:
    // eval alone (the same f as evalWithPdf's, bit for bit).
    const auto [f, materialPdf] =
        strategies_.bsdf ? p.bsdf->evalWithPdf(p.wo, wi) : BsdfValue{p.bsdf->eval(p.wo, wi), 0.0};
    if (f.isBlack()) continue;
    // Whatever route draws the BSDF sample, the weights of both
    // strategies take the material's own sampling pdf (BsdfSample::misPdf).
    const double w =
        area[k] && !chosesEnvironment[k] && area[k]->delta ? 1.0 : misWeight(pdf, materialPdf);
    p.L += (w * std::abs(wi.z) / pdf) * p.beta * f * radiance;
  }
}

bool PathIntegrator::shadowedByShapes(const Ray &shadow, std::size_t except) const {
  const std::vector<AreaLight> &shapes = scene_.lights.shapes;
  for (std::size_t i = 0; i < shapes.size(); ++i)
    if (i != except)
      if (const auto h = shapes[i].intersect(shadow.origin, shadow.direction);
          h && h->distance < shadow.tMax)
        return true;
  return false;
}

bool PathIntegrator::continuePaths(std::span<PathState> path, int depth,
                                   std::span<std::optional<SurfaceHit>> hit,
                                   PathCounters &counters) const {
  const std::size_t n = path.size();
  // The continuation directions by BSDF sampling.
  std::array<Ray, kMaxPaths> next;
  std::array<std::size_t, kMaxPaths> nextOf;
  std::size_t m = 0;
  for (std::size_t k = 0; k < n; ++k) {
    PathState &p = path[k];
    if (!p.alive) continue;
    p.alive = false;
    // The lobe choice is drawn only where a material's own sampler runs (a
    // table's point samples the whole mixture) and has lobes to choose.
    const bool own = (!p.lobe.table || p.lobe.defensive > 0) && p.bsdf->lobeCount() > 1;
    const auto bs = sampleRoute(
        *p.bsdf, p.wo, p.lobe,
        p.lobe.table ? p.lobePoint
                     : RoutePoint{p.samples->primary(SampleLayout::bsdf(depth), p.index)},
        own ? p.samples->number(SampleLayout::lobeChoice(depth), p.index) : 0.0);
    if (!bs) continue;
    // Below the shading hemisphere f = 0, unless the material transmits.
    if (!(bs->wi.z > 0) && !(bs->wi.z < 0 && p.bsdf->transmits())) continue;
    const Vec3 wiWorld = p.sh.frame.toWorld(bs->wi);
    p.beta *= (std::abs(bs->wi.z) / bs->pdf) * bs->f;
    // The MIS weight's BSDF pdf (see addLightSamples); +infinity after a
    // delta lobe, whose ray adds what it meets with weight 1.
    p.lastBsdfPdf = bs->misPdf;
    p.cameraRay = false;
    p.ray = {p.sh.leave(p.wo, bs->wi), wiWorld};
    if (p.beta.isBlack()) continue;
    p.alive = true;
    record(counters, p.ray);
    // Rays after a bounce escape more often than not in an open scene:
    // start loading the map's cell for each ray before tracing them.
    if (light_) p.escape = light_->find(p.ray.direction);
    next[m] = p.ray, nextOf[m++] = k;
  }
  if (m == 0) return false;
  std::array<std::optional<SurfaceHit>, kMaxPaths> traced;
  scene_.geometry.intersect(std::span(next.data(), m), std::span(traced.data(), m));
  for (std::size_t q = 0; q < m; ++q) hit[nextOf[q]] = std::move(traced[q]);
  return true;
}

void PathIntegrator::radiance(std::span<const Ray> rays,
                              std::span<const std::optional<SurfaceHit>> hits,
                              std::span<PixelSamples *const> samples,
                              std::span<const std::size_t> indices, std::span<Rgb> out,
                              PathCounters &counters) const {
  const std::size_t n = rays.size();
  if (n > kMaxPaths || hits.size() != n || samples.size() != n || indices.size() != n ||
      out.size() != n)
    throw std::invalid_argument(
        "PathIntegrator::radiance: at most 16 paths, and one ray, hit, sample "
        "set, index and result for each");
  std::array<PathState, kMaxPaths> path;
  std::array<std::optional<SurfaceHit>, kMaxPaths> hit;
  for (std::size_t k = 0; k < n; ++k) {
    path[k].ray = rays[k];
    path[k].samples = samples[k];
    path[k].index = indices[k];
    hit[k] = hits[k];
    record(counters, rays[k]);
  }
  const std::span<PathState> packet(path.data(), n);
  const std::span<std::optional<SurfaceHit>> packetHits(hit.data(), n);
  for (int depth = 0;; ++depth) {
    if (!arrive(packet, packetHits, depth)) break;
    if (strategies_.bsdf) chooseBsdfStrategies(packet, depth, counters);
    addLightSamples(packet, depth, counters);
    if (!strategies_.bsdf) break;  // the light sample was the whole estimate
    if (!continuePaths(packet, depth, packetHits, counters)) break;
  }

  for (std::size_t k = 0; k < n; ++k) {
    if (path[k].L.isFinite()) {
      out[k] = path[k].L;
    } else {
      ++counters.rejected;
      out[k] = {};
    }
  }
}

}  // namespace nuld
