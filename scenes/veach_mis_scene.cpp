#include "scenes/veach_mis_scene.h"

#include <cmath>
#include <numbers>

#include "materials/disney.h"
#include "materials/lambertian.h"

namespace nuld {

namespace {

// A plate: the rectangle of half-width 4 in x whose edge in the (y, z)
// plane runs from (y0, z0) to (y1, z1) (one unit long), as two triangles
// facing up and forward (towards the camera and the lights).
TriangleMesh plate(std::string name, double y0, double z0, double y1, double z1) {
  return {std::move(name),
          "",
          {{4, y0, z0}, {4, y1, z1}, {-4, y1, z1}, {-4, y0, z0}},
          {},
          {{0, 1, 2}, {0, 2, 3}}};
}

}  // namespace

LoadedScene makeVeachMisScene(LobeChoice lobes) {
  std::vector<TriangleMesh> meshes;
  std::vector<std::shared_ptr<const Bsdf>> materials;
  // The plates, from the back (the smoothest) to the front: Mitsuba's
  // plate1..4 vertices, with GGX alphas 0.005, 0.02, 0.05 and 0.1 (Disney's
  // roughness is the square root of alpha).
  struct Plate {
    double y0, z0, y1, z1, alpha;
  };
  const Plate plates[] = {{-2.70651, 0.25609, -2.08375, -0.526323, 0.005},
                          {-3.28825, 1.36972, -2.83856, 0.476536, 0.02},
                          {-3.73096, 2.70046, -3.43378, 1.74564, 0.05},
                          {-3.99615, 4.0667, -3.82069, 3.08221, 0.1}};
  int k = 0;
  for (const Plate &p : plates) {
    DisneyParams metal;
    metal.baseColor = {0.8, 0.8, 0.8};
    metal.metallic = 1;
    metal.roughness = std::sqrt(p.alpha);
    meshes.push_back(plate("plate" + std::to_string(++k), p.y0, p.z0, p.y1, p.z1));
    materials.push_back(std::make_shared<DisneyBrdf>(metal, lobes));
  }
  // The floor and a back wall: a grey diffuse plane under the plates and
  // one behind them (Mitsuba's floor.obj, a plane curving up into a
  // backdrop, is not reproduced).
  meshes.push_back({"floor",
                    "",
                    {{-10, -4.1, -10}, {10, -4.1, -10}, {10, -4.1, 10}, {-10, -4.1, 10}},
                    {},
                    {{0, 2, 1}, {0, 3, 2}}});
  materials.push_back(std::make_shared<Lambertian>(Rgb::grey(0.4)));
  meshes.push_back({"wall",
                    "",
                    {{-10, -4.1, -2}, {10, -4.1, -2}, {10, 10, -2}, {-10, 10, -2}},
                    {},
                    {{0, 1, 2}, {0, 2, 3}}});
  materials.push_back(std::make_shared<Lambertian>(Rgb::grey(0.4)));
  LoadedScene out{"veach-mis",
                  Scene{EmbreeScene(std::move(meshes)), std::move(materials), std::nullopt, {}}};
  // Four spheres of equal power (radiance times radius squared, 1), and the
  // one that lights the room.
  struct Sphere {
    double x, radius, radiance;
  };
  for (const Sphere &s : {Sphere{-3.75, 0.03333, 901.803}, Sphere{-1.25, 0.1, 100},
                          Sphere{1.25, 0.3, 11.1111}, Sphere{3.75, 0.9, 1.23457}})
    out.scene.lights.shapes.push_back(
        AreaLight::sphere({s.x, 0, 0}, s.radius, Rgb::grey(s.radiance)));
  out.scene.lights.shapes.push_back(AreaLight::sphere({10, 10, 4}, 0.5, Rgb::grey(800)));
  finishLights(out.scene);
  out.scene.lobeChoice = lobes;
  // Mitsuba's 25-degree field of view is the image's width; this camera's
  // is its shorter side's: 2 atan(tan(12.5 deg) 512 / 768).
  const double fov = 2 * std::atan(std::tan(12.5 * std::numbers::pi / 180) * 512.0 / 768.0) * 180 /
                     std::numbers::pi;
  out.scene.camera = {{0, 6, 27.5}, {0, -1.5, 2.5}, {0, 1, 0}, fov, false};
  out.settings.width = 768;
  out.settings.height = 512;
  out.settings.spp = 16;
  out.settings.integrator = IntegratorKind::Direct;
  return out;
}

}  // namespace nuld
