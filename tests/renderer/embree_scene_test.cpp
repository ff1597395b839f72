// Ray queries against hand-placed triangles, where the answers are known.

#include "renderer/embree_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "renderer/camera.h"

namespace nuld {
namespace {

// A unit square in the plane z = 0, wound to face +z, plus a degenerate
// triangle (all three vertices on a line).
std::vector<TriangleMesh> quadAndDegenerate() {
  TriangleMesh quad;
  quad.name = "quad";
  quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  TriangleMesh line;
  line.name = "degenerate";
  line.positions = {{0, 0, 2}, {1, 0, 2}, {2, 0, 2}};
  line.triangles = {{0, 1, 2}};
  return {quad, line};
}

TEST(EmbreeScene, HitsAtTheExpectedDistanceWithTheWindingNormal) {
  const EmbreeScene scene(quadAndDegenerate());
  const auto hit = scene.intersect({{0.25, 0.5, 3}, {0, 0, -1}});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 3, 1e-6);
  EXPECT_EQ(hit->mesh, 0u);
  EXPECT_NEAR(hit->position.x, 0.25, 1e-6);
  EXPECT_NEAR(hit->position.y, 0.5, 1e-6);
  EXPECT_NEAR(hit->geometricNormal.z, 1, 1e-12);
  EXPECT_NEAR(hit->shadingNormal.z, 1, 1e-12);
}

TEST(EmbreeScene, MissesAndRespectsTMax) {
  const EmbreeScene scene(quadAndDegenerate());
  EXPECT_FALSE(scene.intersect({{1.5, 0, 3}, {0, 0, -1}}));
  EXPECT_FALSE(scene.intersect({{0, 0, 3}, {0, 0, 1}}));
  EXPECT_FALSE(scene.intersect({{0, 0, 3}, {0, 0, -1}, 2.5}));
  EXPECT_TRUE(scene.occluded({{0, 0, 3}, {0, 0, -1}}));
  EXPECT_FALSE(scene.occluded({{0, 0, 3}, {0, 0, -1}, 2.5}));
  EXPECT_FALSE(scene.occluded({{3, 3, 3}, {0, 0, 1}}));
}

// Checks hits[k] against intersect(rays[k]), the oracle, with t and the
// position equal to within `tolerance` (0: exactly); returns the hit count.
int compareWithSingleRays(const EmbreeScene &scene, const std::vector<Ray> &rays,
                          const std::vector<std::optional<SurfaceHit>> &hits, double tolerance) {
  int hitCount = 0;
  for (std::size_t k = 0; k < rays.size(); ++k) {
    const auto single = scene.intersect(rays[k]);
    EXPECT_EQ(bool(hits[k]), bool(single)) << "ray " << k;
    if (!single || !hits[k]) continue;
    ++hitCount;
    EXPECT_NEAR(hits[k]->t, single->t, tolerance) << "ray " << k;
    EXPECT_EQ(hits[k]->mesh, single->mesh);
    EXPECT_EQ(hits[k]->triangle, single->triangle);
    EXPECT_NEAR(length(hits[k]->position - single->position), 0, tolerance);
    EXPECT_EQ(hits[k]->geometricNormal, single->geometricNormal);
    EXPECT_EQ(hits[k]->shadingNormal, single->shadingNormal);
  }
  return hitCount;
}

// Packets are checked against single rays, the oracle: 37 rays (two full
// packets and a partial one) from a camera-like fan, some hitting the quad
// (through either triangle), some missing it, one stopped short of it by tMax).
TEST(EmbreeScene, CoherentPacketsFindTheHitsOfSingleRays) {
  const EmbreeScene scene(quadAndDegenerate());
  std::vector<Ray> rays;
  for (int k = 0; k < 37; ++k) {
    const double a = -1.6 + 3.2 * k / 36.0, b = 0.3 * std::sin(double(k));
    rays.push_back({{0.1, 0.2, 3}, normalize(Vec3{a, b, -3})});
  }
  rays[18].tMax = 2.0;  // straight down: it hits at t ~ 3 without the limit
  std::vector<std::optional<SurfaceHit>> hits(rays.size());
  scene.intersectCoherent(rays, hits);
  const int hitCount = compareWithSingleRays(scene, rays, hits, 1e-5);
  EXPECT_GT(hitCount, 10);
  EXPECT_LT(hitCount, 36);
  EXPECT_FALSE(hits[18]);
  // No rays is a valid request; a hit span of another length is refused.
  scene.intersectCoherent({}, {});
  EXPECT_THROW(scene.intersectCoherent(rays, std::span(hits.data(), 3)), std::invalid_argument);
}

// The batch form of intersect() must give exactly the single-ray hits (it
// only reorders memory reads): unrelated rays from scattered origins, more
// than one group of 16, including misses and one stopped short by tMax.
TEST(EmbreeScene, BatchedIncoherentRaysFindExactlyTheSingleRayHits) {
  const EmbreeScene scene(quadAndDegenerate());
  std::vector<Ray> rays;
  for (int k = 0; k < 41; ++k) {
    const double a = std::sin(1.7 * k), b = std::cos(2.3 * k);
    const Vec3 origin{0.8 * a, 0.8 * b, k % 2 ? 2.0 : -2.0};
    const Vec3 target{0.5 * std::sin(0.9 * k), 0.5 * std::cos(1.1 * k), 0};
    rays.push_back({origin, normalize(target - origin + Vec3{0, 0, k % 7 == 0 ? 5.0 : 0.0})});
  }
  rays[4].tMax = 0.5;
  std::vector<std::optional<SurfaceHit>> hits(rays.size());
  scene.intersect(rays, hits);
  const int hitCount = compareWithSingleRays(scene, rays, hits, 0.0);
  EXPECT_GT(hitCount, 5);
  EXPECT_LT(hitCount, 40);
  EXPECT_FALSE(hits[4]);
  scene.intersect(std::span<const Ray>{}, {});
  EXPECT_THROW(scene.intersect(rays, std::span(hits.data(), 3)), std::invalid_argument);
}

TEST(EmbreeScene, DegenerateTrianglesNeverProduceNonFiniteNormals) {
  const EmbreeScene scene(quadAndDegenerate());
  // Rays along the degenerate triangle's line and through it.
  for (const Ray &r : {Ray{{-1, 0, 2}, {1, 0, 0}}, Ray{{1, 0, 4}, {0, 0, -1}}}) {
    if (const auto hit = scene.intersect(r)) {
      EXPECT_TRUE(isFinite(hit->geometricNormal));
      EXPECT_TRUE(isFinite(hit->shadingNormal));
    }
  }
}

TEST(EmbreeScene, InterpolatesVertexNormalsAndKeepsTheGeometricNormalOnTheirSide) {
  TriangleMesh tri;
  tri.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  tri.triangles = {{0, 2, 1}};                                     // wound to face -z ...
  tri.normals = {{0, 0, 1}, {0, 0, 1}, normalize(Vec3{0, 1, 1})};  // ... normals say +z
  const EmbreeScene scene({tri});
  const auto hit = scene.intersect({{0, 0, 1}, {0, 0, -1}});
  ASSERT_TRUE(hit);
  EXPECT_GT(hit->geometricNormal.z, 0.999);
  EXPECT_GT(hit->shadingNormal.y, 0.01);
  EXPECT_NEAR(length(hit->shadingNormal), 1, 1e-12);
}

TEST(EmbreeScene, RejectsOutOfRangeIndicesAndNonFiniteVertices) {
  TriangleMesh bad;
  bad.name = "bad";
  bad.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  bad.triangles = {{0, 1, 3}};
  EXPECT_THROW(EmbreeScene({bad}), std::invalid_argument);
  bad.triangles = {{0, 1, 2}};
  bad.positions[1].x = std::nan("");
  EXPECT_THROW(EmbreeScene({bad}), std::invalid_argument);
}

TEST(Camera, CentreRayLooksAtTheTargetAndMirrorFlipsX) {
  const CameraSettings s{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 60, false};
  const PerspectiveCamera cam(s, 200, 100);
  const Ray centre = cam.generateRay({100, 50});
  EXPECT_NEAR(centre.direction.z, -1, 1e-12);
  // Right side of the image is +x for a right-handed camera looking down -z.
  EXPECT_GT(cam.generateRay({200, 50}).direction.x, 0);
  EXPECT_GT(cam.generateRay({100, 0}).direction.y, 0);  // row 0 is the top
  CameraSettings m = s;
  m.mirrorX = true;
  EXPECT_LT(PerspectiveCamera(m, 200, 100).generateRay({200, 50}).direction.x, 0);
  // fov spans the shorter side (the height here): the top edge is 30 degrees up.
  const Vec3 top = cam.generateRay({100, 0}).direction;
  EXPECT_NEAR(std::atan2(top.y, -top.z), std::numbers::pi / 6, 1e-12);
}

TEST(Camera, RejectsDegenerateSettings) {
  EXPECT_THROW(PerspectiveCamera({{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 40, false}, 10, 10),
               std::invalid_argument);
  EXPECT_THROW(PerspectiveCamera({{0, 0, 5}, {0, 0, 0}, {0, 0, 1}, 40, false}, 10, 10),
               std::invalid_argument);
  EXPECT_THROW(PerspectiveCamera({{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 180, false}, 10, 10),
               std::invalid_argument);
}

}  // namespace
}  // namespace nuld
