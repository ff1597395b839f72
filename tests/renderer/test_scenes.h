#pragma once
// Small scenes built in code for the renderer tests.

#include <memory>

#include "materials/lambertian.h"
#include "renderer/scene.h"
#include "renderer/shapes.h"
#include "sampler/io/image_io.h"

namespace nuld::test {

// A constant-radiance environment map.
inline Image constantMap(float value, int width = 16, int height = 8) {
  return Image{width, height, 3, std::vector<float>(std::size_t(width) * height * 3, value)};
}

// Writes a small constant map with one hot pixel to `path`: a file-backed
// light whose target differs from a constant map's.
inline void writeHotPixelMap(const std::string &path) {
  Image map = constantMap(1.0f, 16, 8);
  map.at(3, 2, 0) = 50.0f;
  writeImage(path, map);
}

// A UV sphere of radius 1 at the origin. It is convex, so light that leaves
// it never returns (white-furnace tests rely on that).
inline TriangleMesh unitSphere(int rings = 24, int segments = 48) {
  return makeSphere({0, 0, 0}, 1.0, rings, segments, "sphere");
}

inline Scene sceneWith(std::vector<TriangleMesh> meshes,
                       std::vector<std::shared_ptr<const Bsdf>> materials, std::optional<Image> map,
                       CameraSettings camera = {}, PixelWeight weight = PixelWeight::Luminance) {
  Scene s{EmbreeScene(std::move(meshes)), std::move(materials), std::nullopt, camera};
  if (map) s.environment.emplace(std::move(*map), 1.0, 0.0, "test-map", Vec3{0, 1, 0}, weight);
  return s;
}

}  // namespace nuld::test
