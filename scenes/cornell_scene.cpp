#include "scenes/cornell_scene.h"

#include "materials/lambertian.h"

namespace nuld {

namespace {

// Mitsuba 3's RGB reflectances and the light's radiance (mitsuba.cornell_box).
constexpr Rgb kWhite{0.885809, 0.698859, 0.666422}, kRed{0.570068, 0.0430135, 0.0443706},
    kGreen{0.105421, 0.37798, 0.076425}, kLight{18.387, 13.9873, 6.75357};

// The parallelogram corner + [0, 1] a + [0, 1] b as two triangles wound so
// that cross(a, b) is their normal.
TriangleMesh quad(std::string name, Vec3 corner, Vec3 a, Vec3 b) {
  return {std::move(name),
          "",
          {corner, corner + a, corner + a + b, corner + b},
          {},
          {{0, 1, 2}, {0, 2, 3}}};
}

// Mitsuba's cube [-1, 1]^3 under the affine map x -> c + X x.x + Y x.y + Z x.z.
TriangleMesh box(std::string name, Vec3 c, Vec3 X, Vec3 Y, Vec3 Z) {
  TriangleMesh m{std::move(name), "", {}, {}, {}};
  for (int k = 0; k < 8; ++k)
    m.positions.push_back(c + (k & 1 ? 1.0 : -1.0) * X + (k & 2 ? 1.0 : -1.0) * Y +
                          (k & 4 ? 1.0 : -1.0) * Z);
  // Each face outward: corners by bits (x, y, z).
  const std::uint32_t faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                     {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto &f : faces) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  return m;
}

}  // namespace

LoadedScene makeCornellScene() {
  std::vector<TriangleMesh> meshes;
  std::vector<std::shared_ptr<const Bsdf>> materials;
  const auto white = std::make_shared<Lambertian>(kWhite);
  const auto add = [&](TriangleMesh mesh, std::shared_ptr<const Bsdf> bsdf) {
    meshes.push_back(std::move(mesh));
    materials.push_back(std::move(bsdf));
  };
  add(quad("floor", {-1, -1, -1}, {0, 0, 2}, {2, 0, 0}), white);
  add(quad("ceiling", {-1, 1, -1}, {2, 0, 0}, {0, 0, 2}), white);
  add(quad("back", {-1, -1, -1}, {2, 0, 0}, {0, 2, 0}), white);
  add(quad("red-wall", {-1, -1, -1}, {0, 2, 0}, {0, 0, 2}), std::make_shared<Lambertian>(kRed));
  add(quad("green-wall", {1, -1, -1}, {0, 0, 2}, {0, 2, 0}), std::make_shared<Lambertian>(kGreen));
  add(box("small-box", {0.335, -0.7, 0.38}, {0.286891, 0, 0.0877115}, {0, 0.3, 0},
          {-0.0877115, 0, 0.286891}),
      white);
  add(box("large-box", {-0.33, -0.4, -0.28}, {0.28491, 0, -0.0939491}, {0, 0.61, 0},
          {0.0939491, 0, 0.28491}),
      white);
  LoadedScene out{"cornell",
                  Scene{EmbreeScene(std::move(meshes)), std::move(materials), std::nullopt, {}}};
  // The light: x in [-0.23, 0.23], z in [-0.18, 0.2] at y = 0.99, facing
  // down (cross(+x, +z) = -y).
  out.scene.lights.shapes.push_back(
      AreaLight::rectangle({-0.23, 0.99, -0.18}, {0.46, 0, 0}, {0, 0, 0.38}, kLight));
  finishLights(out.scene);
  out.scene.camera = {{0, 0, 3.9}, {0, 0, 0}, {0, 1, 0}, 39.3077, false};
  out.settings.width = 256;
  out.settings.height = 256;
  out.settings.spp = 16;
  out.settings.integrator = IntegratorKind::Path;
  out.settings.maxDepth = 8;
  return out;
}

}  // namespace nuld
