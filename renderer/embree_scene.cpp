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
  const double inf = std::numeric_limits<double>::infinity();
  lo_ = {inf, inf, inf};
  hi_ = -lo_;
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
      lo_ = min(lo_, p);
      hi_ = max(hi_, p);
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
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

  SurfaceHit hit;
  hit.t = rh.ray.tfar;
  hit.mesh = rh.hit.geomID;
  hit.triangle = rh.hit.primID;
  const TriangleMesh &mesh = meshes_[hit.mesh];
  const auto &tri = mesh.triangles[hit.triangle];
  const Vec3 p0 = mesh.positions[tri[0]], p1 = mesh.positions[tri[1]], p2 = mesh.positions[tri[2]];
  const double b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1 - b1 - b2;
  // The position from barycentrics in double precision is closer to the
  // surface than origin + t * direction from a float t.
  hit.position = b0 * p0 + b1 * p1 + b2 * p2;
  Vec3 ng = cross(p1 - p0, p2 - p0);
  const double len = length(ng);
  // A hit on a degenerate (zero-area) triangle has no normal; face the ray.
  ng = len > 0 && std::isfinite(len) ? ng / len : -normalize(ray.direction);
  hit.geometricNormal = ng;
  hit.shadingNormal = ng;
  if (!mesh.normals.empty()) {
    const Vec3 ns =
        b0 * mesh.normals[tri[0]] + b1 * mesh.normals[tri[1]] + b2 * mesh.normals[tri[2]];
    const double nlen = length(ns);
    if (nlen > 1e-12 && std::isfinite(nlen)) hit.shadingNormal = ns / nlen;
    // Vertex normals define the outside; keep the geometric normal on that side.
    if (dot(hit.shadingNormal, ng) < 0) hit.geometricNormal = -ng;
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
