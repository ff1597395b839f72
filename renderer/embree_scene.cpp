#include "renderer/embree_scene.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace nuld {

struct EmbreeScene::Handles {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Handles() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

void throwOnError(RTCDevice device, const char *what) {
  const RTCError err = rtcGetDeviceError(device);
  if (err != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree: ") + what + " failed (error " +
                             std::to_string(int(err)) + ")");
}

}  // namespace

EmbreeScene::EmbreeScene(std::vector<TriangleMesh> meshes)
    : handles_(std::make_unique<Handles>()), meshes_(std::move(meshes)) {
  handles_->device = rtcNewDevice(nullptr);
  if (!handles_->device) throw std::runtime_error("Embree: cannot create a device");
  handles_->scene = rtcNewScene(handles_->device);
  rtcSetSceneBuildQuality(handles_->scene, RTC_BUILD_QUALITY_HIGH);
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const TriangleMesh &mesh = meshes_[m];
    const std::size_t nv = mesh.positions.size();
    for (const auto &tri : mesh.triangles)
      for (std::uint32_t i : tri)
        if (i >= nv)
          throw std::invalid_argument("mesh '" + mesh.name + "': vertex index " +
                                      std::to_string(i) + " out of range (" + std::to_string(nv) +
                                      " vertices)");
    RTCGeometry geom = rtcNewGeometry(handles_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto *v = static_cast<float *>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
    for (std::size_t i = 0; i < nv; ++i) {
      const Vec3 p = mesh.positions[i];
      if (!isFinite(p))
        throw std::invalid_argument("mesh '" + mesh.name + "': vertex " + std::to_string(i) +
                                    " is not finite");
      v[3 * i] = float(p.x), v[3 * i + 1] = float(p.y), v[3 * i + 2] = float(p.z);
    }
    auto *idx = static_cast<unsigned *>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), mesh.triangles.size()));
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) idx[3 * t + k] = mesh.triangles[t][k];
    rtcCommitGeometry(geom);
    // Geometry ids follow mesh order (a fresh scene numbers them 0, 1, ...).
    rtcAttachGeometryByID(handles_->scene, geom, unsigned(m));
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(handles_->scene);
  throwOnError(handles_->device, "building the scene");
}

EmbreeScene::~EmbreeScene() = default;
EmbreeScene::EmbreeScene(EmbreeScene &&) noexcept = default;
EmbreeScene &EmbreeScene::operator=(EmbreeScene &&) noexcept = default;

std::size_t EmbreeScene::triangleCount() const {
  std::size_t n = 0;
  for (const auto &m : meshes_) n += m.triangles.size();
  return n;
}

namespace {

RTCRayHit makeRayHit(const Ray &ray) {
  RTCRayHit rh{};
  rh.ray.org_x = float(ray.origin.x), rh.ray.org_y = float(ray.origin.y);
  rh.ray.org_z = float(ray.origin.z);
  rh.ray.dir_x = float(ray.direction.x), rh.ray.dir_y = float(ray.direction.y);
  rh.ray.dir_z = float(ray.direction.z);
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = std::isfinite(ray.tMax) ? float(ray.tMax) : std::numeric_limits<float>::infinity();
  rh.ray.mask = 0xffffffffu;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace

std::optional<SurfaceHit> EmbreeScene::intersect(const Ray &ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = makeRayHit(ray);
  rtcIntersect1(handles_->scene, &context, &rh);
  return surfaceHit(ray, rh.ray.tfar, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v);
}

void EmbreeScene::intersectCoherent(std::span<const Ray> rays,
                                    std::span<std::optional<SurfaceHit>> hits) const {
  if (hits.size() != rays.size())
    throw std::invalid_argument("intersectCoherent: one hit slot per ray");
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  constexpr std::size_t kPacket = 16;
  for (std::size_t first = 0; first < rays.size(); first += kPacket) {
    const std::size_t n = std::min(kPacket, rays.size() - first);
    alignas(64) RTCRayHit16 packet;
    alignas(64) int valid[kPacket];
    for (std::size_t k = 0; k < kPacket; ++k) {
      // Lanes past the last ray are masked off (valid = 0) but still hold a
      // copy of a real ray, so no lane carries uninitialized values.
      const RTCRayHit one = makeRayHit(rays[first + std::min(k, n - 1)]);
      valid[k] = k < n ? -1 : 0;
      packet.ray.org_x[k] = one.ray.org_x, packet.ray.org_y[k] = one.ray.org_y;
      packet.ray.org_z[k] = one.ray.org_z;
      packet.ray.dir_x[k] = one.ray.dir_x, packet.ray.dir_y[k] = one.ray.dir_y;
      packet.ray.dir_z[k] = one.ray.dir_z;
      packet.ray.tnear[k] = one.ray.tnear, packet.ray.tfar[k] = one.ray.tfar;
      packet.ray.time[k] = 0, packet.ray.mask[k] = one.ray.mask;
      packet.ray.id[k] = 0, packet.ray.flags[k] = 0;
      packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, handles_->scene, &context, &packet);
    for (std::size_t k = 0; k < n; ++k)
      hits[first + k] = surfaceHit(rays[first + k], packet.ray.tfar[k], packet.hit.geomID[k],
                                   packet.hit.primID[k], packet.hit.u[k], packet.hit.v[k]);
  }
}

void EmbreeScene::intersect(std::span<const Ray> rays,
                            std::span<std::optional<SurfaceHit>> hits) const {
  if (hits.size() != rays.size()) throw std::invalid_argument("intersect: one hit slot per ray");
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  constexpr std::size_t kGroup = 16;
  for (std::size_t first = 0; first < rays.size(); first += kGroup) {
    const std::size_t n = std::min(kGroup, rays.size() - first);
    RTCRayHit rh[kGroup];
    for (std::size_t k = 0; k < n; ++k) {
      rh[k] = makeRayHit(rays[first + k]);
      rtcIntersect1(handles_->scene, &context, &rh[k]);
      if (rh[k].hit.geomID != RTC_INVALID_GEOMETRY_ID)
        __builtin_prefetch(&meshes_[rh[k].hit.geomID].triangles[rh[k].hit.primID]);
    }
    // The vertices once their indices have arrived, then the hits.
    for (std::size_t k = 0; k < n; ++k) {
      if (rh[k].hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
      const TriangleMesh &mesh = meshes_[rh[k].hit.geomID];
      for (std::uint32_t v : mesh.triangles[rh[k].hit.primID]) {
        __builtin_prefetch(&mesh.positions[v]);
        if (!mesh.normals.empty()) __builtin_prefetch(&mesh.normals[v]);
      }
    }
    for (std::size_t k = 0; k < n; ++k)
      hits[first + k] = surfaceHit(rays[first + k], rh[k].ray.tfar, rh[k].hit.geomID,
                                   rh[k].hit.primID, rh[k].hit.u, rh[k].hit.v);
  }
}

std::optional<SurfaceHit> EmbreeScene::surfaceHit(const Ray &ray, float t, unsigned meshId,
                                                  unsigned triangle, float u, float v) const {
  if (meshId == RTC_INVALID_GEOMETRY_ID) return std::nullopt;  // the ray missed
  SurfaceHit hit;
  hit.t = t;
  hit.mesh = meshId;
  hit.triangle = triangle;
  const TriangleMesh &mesh = meshes_[hit.mesh];
  const auto &tri = mesh.triangles[hit.triangle];
  const Vec3 p0 = mesh.positions[tri[0]], p1 = mesh.positions[tri[1]], p2 = mesh.positions[tri[2]];
  const double b1 = u, b2 = v, b0 = 1 - b1 - b2;
  // The position from barycentrics in double precision is closer to the
  // surface than origin + t * direction from a float t.
  hit.position = b0 * p0 + b1 * p1 + b2 * p2;
  Vec3 ng = cross(p1 - p0, p2 - p0);
  const double len = length(ng);
  // A hit on a degenerate (zero-area) triangle has no normal; face the ray.
  ng = len > 0 && std::isfinite(len) ? ng / len : -normalize(ray.direction);
  hit.geometricNormal = ng;
  hit.shadingNormal = ng;
  if (!mesh.uvs.empty()) {
    const Point2 t0 = mesh.uvs[tri[0]], t1 = mesh.uvs[tri[1]], t2 = mesh.uvs[tri[2]];
    hit.uv = {b0 * t0.x + b1 * t1.x + b2 * t2.x, b0 * t0.y + b1 * t1.y + b2 * t2.y};
  }
  if (!mesh.normals.empty()) {
    const Vec3 ns =
        b0 * mesh.normals[tri[0]] + b1 * mesh.normals[tri[1]] + b2 * mesh.normals[tri[2]];
    const double nlen = length(ns);
    if (nlen > 1e-12 && std::isfinite(nlen)) hit.shadingNormal = ns / nlen;
    // Vertex normals define the outside; keep the geometric normal on that side.
    if (dot(hit.shadingNormal, ng) < 0) hit.geometricNormal = -ng;
    const double b[3] = {b0, b1, b2};
    Vec3 shading{};
    for (int k = 0; k < 3; ++k) {
      const Vec3 pk = mesh.positions[tri[k]], nk = mesh.normals[tri[k]];
      shading += b[k] * (hit.position - dot(hit.position - pk, nk) * nk);
    }
    if (isFinite(shading)) hit.shadingOffset = shading - hit.position;
  }
  return hit;
}

bool EmbreeScene::occluded(const Ray &ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r = makeRayHit(ray).ray;
  rtcOccluded1(handles_->scene, &context, &r);
  return r.tfar < 0;  // Embree sets tfar to -inf on a hit
}

float EmbreeScene::rawIntersect(const float origin[3], const float direction[3]) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = origin[0], rh.ray.org_y = origin[1], rh.ray.org_z = origin[2];
  rh.ray.dir_x = direction[0], rh.ray.dir_y = direction[1], rh.ray.dir_z = direction[2];
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = 0xffffffffu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(handles_->scene, &context, &rh);
  return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::infinity()
                                                  : rh.ray.tfar;
}

Vec3 offsetRayOrigin(Vec3 p, Vec3 n, Vec3 direction) {
  const double scale = std::max({1.0, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  const double eps = 1e-4 * scale;
  return p + (dot(direction, n) >= 0 ? eps : -eps) * n;
}

}  // namespace nuld
