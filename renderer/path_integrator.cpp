#include "renderer/path_integrator.h"

#include <cmath>
#include <stdexcept>

#include "materials/frame.h"

namespace nuld {

IntegratorKind parseIntegrator(const std::string &name) {
  if (name == "path") return IntegratorKind::Path;
  if (name == "direct") return IntegratorKind::Direct;
  if (name == "light") return IntegratorKind::Light;
  throw std::invalid_argument("unknown integrator '" + name + "': expected path, direct or light");
}

std::string toString(IntegratorKind k) {
  switch (k) {
    case IntegratorKind::Path: return "path";
    case IntegratorKind::Direct: return "direct";
    case IntegratorKind::Light: return "light";
  }
  return "?";
}

PathIntegrator::PathIntegrator(const Scene &scene, IntegratorKind kind, int maxDepth)
    : scene_(scene),
      maxDepth_(kind == IntegratorKind::Path ? maxDepth : 1),
      lightOnly_(kind == IntegratorKind::Light) {
  if (maxDepth < 1) throw std::invalid_argument("max depth must be at least 1");
}

namespace {

// The shading frame at a hit, turned to the side the path arrives from (every
// material is two-sided). A shading normal that faces away from wo is
// replaced by the geometric one, which always faces wo.
struct Shading {
  Frame frame;
  Vec3 ng;
};

Shading shadingAt(const SurfaceHit &hit, Vec3 wo) {
  Vec3 ng = hit.geometricNormal, ns = hit.shadingNormal;
  if (dot(wo, ng) < 0) ng = -ng, ns = -ns;
  if (dot(wo, ns) <= 0) ns = ng;
  return {Frame::fromNormal(ns), ng};
}

void record(PathCounters &c, const Ray &r) {
  ++c.rays;
  if (c.recorder)
    c.recorder->push_back({{float(r.origin.x), float(r.origin.y), float(r.origin.z)},
                           {float(r.direction.x), float(r.direction.y), float(r.direction.z)}});
}

// The light sample of sample `index` at bounce `depth`. At the first bounce
// nearly every sample of a pixel needs one, so all N are drawn in one batch
// whose cache misses on a large map overlap; deeper, most paths have ended
// and a batch would mostly draw samples nobody uses. Same values either way.
std::optional<LightSample> lightSample(const EnvironmentLight &light, PixelSamples &samples,
                                       int depth, std::size_t index) {
  const std::uint32_t pair = SamplePairs::light(depth);
  if (depth == 0) return samples.lightSample(light, pair, index);
  const Point2 *x = samples.distributed(*light.target(), pair, index);
  return x ? light.sampleTarget(*x) : light.sample(samples.primary(pair, index));
}

}  // namespace

Rgb PathIntegrator::radiance(const Ray &cameraRay, const std::optional<SurfaceHit> &cameraHit,
                             PixelSamples &samples, std::size_t index,
                             PathCounters &counters) const {
  const EnvironmentLight *light = scene_.environment ? &*scene_.environment : nullptr;
  Rgb L, beta{1, 1, 1};
  Ray ray = cameraRay;
  double lastBsdfPdf = 0;  // 0: the camera ray (no MIS on what it sees)
  for (int depth = 0;; ++depth) {
    record(counters, ray);
    // Rays after a bounce escape more often than not in an open scene: start
    // loading the map's cell for the ray's direction before tracing it.
    // Camera rays mostly hit, so their lookup waits until they escape.
    EnvironmentLight::Lookup escape;
    if (light && depth > 0) escape = light->find(ray.direction);
    std::optional<SurfaceHit> traced;
    if (depth > 0) traced = scene_.geometry.intersect(ray);
    const std::optional<SurfaceHit> &hit = depth > 0 ? traced : cameraHit;
    if (!hit) {
      if (light) {
        double lightPdf;
        const Rgb Le = light->radiance(depth > 0 ? escape : light->find(ray.direction), lightPdf);
        const double w = lastBsdfPdf > 0 ? powerHeuristic(lastBsdfPdf, lightPdf) : 1.0;
        L += w * beta * Le;
      }
      break;
    }
    if (depth >= maxDepth_) break;

    const Bsdf &bsdf = *scene_.materials[hit->mesh];
    const Vec3 woWorld = -ray.direction;
    const Shading sh = shadingAt(*hit, woWorld);
    const Vec3 wo = sh.frame.toLocal(woWorld);
    if (!(wo.z > 0)) break;

    // Next-event estimation of the environment.
    if (light && light->target()) {
      const auto ls = lightSample(*light, samples, depth, index);
      if (ls && dot(ls->wi, sh.ng) > 0) {
        const Vec3 wi = sh.frame.toLocal(ls->wi);
        const auto [f, bsdfPdf] = bsdf.evalWithPdf(wo, wi);
        if (wi.z > 0 && !f.isBlack()) {
          const Ray shadow{offsetRayOrigin(hit->position, sh.ng, ls->wi), ls->wi};
          record(counters, shadow);
          if (!scene_.geometry.occluded(shadow)) {
            const double w = lightOnly_ ? 1.0 : powerHeuristic(ls->pdf, bsdfPdf);
            L += (w * wi.z / ls->pdf) * beta * f * ls->radiance;
          }
        }
      }
    }

    if (lightOnly_) break;  // the light sample was the whole estimate

    // The continuation direction by BSDF sampling.
    const auto bs = bsdf.sample(wo, samples.primary(SamplePairs::bsdf(depth), index));
    if (!bs || !(bs->pdf > 0)) break;
    const Vec3 wiWorld = sh.frame.toWorld(bs->wi);
    if (dot(wiWorld, sh.ng) <= 0) break;  // below the geometric surface: a light leak
    beta *= (bs->wi.z / bs->pdf) * bs->f;
    lastBsdfPdf = bs->pdf;
    ray = {offsetRayOrigin(hit->position, sh.ng, wiWorld), wiWorld};

    // Russian roulette (pbrt-v4's rule) once the path has bounced twice.
    if (depth >= 1 && beta.maxComponent() < 1) {
      const double q = std::max(0.0, 1 - beta.maxComponent());
      if (samples.primary(SamplePairs::roulette(depth), index).x < q) break;
      beta = beta / (1 - q);
    }
    if (beta.isBlack()) break;
  }
  if (!L.isFinite()) {
    ++counters.rejected;
    return {};
  }
  return L;
}

}  // namespace nuld
