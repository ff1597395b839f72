// Textures (renderer/texture.h) and textured Disney materials
// (renderer/textured_material.h): bilinear lookups by hand on 2 x 2 images,
// glTF's wrap modes, the sRGB decode against its definition, and a textured
// floor that renders exactly as the untextured material of its texels'
// values.
#include <gtest/gtest.h>

#include <cmath>

#include "backends/backend_registry.h"
#include "renderer/render.h"
#include "renderer/textured_material.h"
#include "tests/renderer/test_scenes.h"

namespace nuld {
namespace {

// Texels (x, y): 0 at (0, 0), 1 at (1, 0), 2 at (0, 1), 3 at (1, 1), grey.
Image ramp2x2() { return Image{2, 2, 1, {0, 1, 2, 3}}; }

TEST(Texture, BilinearBetweenTexelCentres) {
  const Texture t(ramp2x2(), Texture::Encoding::Linear, Texture::Wrap::Clamp, Texture::Wrap::Clamp);
  EXPECT_DOUBLE_EQ(t.lookup({0.25, 0.25}).g, 0.0);  // texel (0, 0)'s centre
  EXPECT_DOUBLE_EQ(t.lookup({0.75, 0.25}).g, 1.0);
  EXPECT_DOUBLE_EQ(t.lookup({0.25, 0.75}).g, 2.0);  // v runs down the rows
  EXPECT_DOUBLE_EQ(t.lookup({0.5, 0.5}).g, 1.5);    // the mean of all four
  EXPECT_DOUBLE_EQ(t.lookup({0.5, 0.25}).g, 0.5);
  // Clamped beyond the edge texels' centres.
  EXPECT_DOUBLE_EQ(t.lookup({-3, 0.25}).g, 0.0);
  EXPECT_DOUBLE_EQ(t.lookup({0.9, 0.9}).g, 3.0);
}

TEST(Texture, WrapModes) {
  const Texture repeat(ramp2x2(), Texture::Encoding::Linear);
  EXPECT_NEAR(repeat.lookup({1.25, 0.25}).g, repeat.lookup({0.25, 0.25}).g, 1e-12);
  EXPECT_NEAR(repeat.lookup({-0.75, 0.25}).g, 0.0, 1e-12);
  // Between the last and first columns: half of each.
  EXPECT_NEAR(repeat.lookup({0.0, 0.25}).g, 0.5, 1e-12);
  const Texture mirror(ramp2x2(), Texture::Encoding::Linear, Texture::Wrap::Mirror,
                       Texture::Wrap::Mirror);
  // u in [1, 2) reads the image backwards: 1.25 is texel 1's centre.
  EXPECT_NEAR(mirror.lookup({1.25, 0.25}).g, 1.0, 1e-12);
  EXPECT_NEAR(mirror.lookup({1.75, 0.25}).g, 0.0, 1e-12);
  EXPECT_NEAR(mirror.lookup({0.0, 0.25}).g, 0.0, 1e-12);  // the edge is its own mirror
}

TEST(Texture, SrgbDecodeAndStiffCoordinates) {
  // IEC 61966-2-1: the linear segment below 0.04045, the power above.
  EXPECT_NEAR(srgbToLinear(0.02), 0.02 / 12.92, 1e-15);
  EXPECT_NEAR(srgbToLinear(0.5), std::pow(0.555 / 1.055, 2.4), 1e-15);
  EXPECT_NEAR(srgbToLinear(1.0), 1.0, 1e-15);
  const Texture t(Image{1, 1, 3, {0.5f, 1.0f, 0.0f}}, Texture::Encoding::Srgb);
  EXPECT_NEAR(t.texel(0, 0).r, srgbToLinear(0.5f), 1e-7);
  EXPECT_EQ(t.texel(0, 0).b, 0.0);
  for (const double u :
       {1e300, -1e300, std::nan(""), std::numeric_limits<double>::infinity(), 1e15 + 0.3})
    EXPECT_TRUE(t.lookup({u, u}).isFinite()) << u;
  EXPECT_THROW(Texture(Image{}, Texture::Encoding::Linear), std::invalid_argument);
}

// A floor whose texture is one colour everywhere renders as the plain
// material of that colour, sample for sample; so does a metallic-roughness
// texture against the factors it scales.
TEST(TexturedDisney, UniformTexturesRenderAsTheirValues) {
  DisneyParams plain;
  plain.baseColor = {0.25, 0.5, 0.75};
  plain.metallic = 0.5;
  plain.roughness = 0.3;
  TexturedDisney textured;
  textured.factors.baseColor = {0.5, 1, 1};
  textured.factors.metallic = 1;
  textured.factors.roughness = 0.6;
  textured.baseColor =
      std::make_shared<Texture>(Image{2, 2, 3,
                                      std::vector<float>{0.5f, 0.5f, 0.75f, 0.5f, 0.5f, 0.75f, 0.5f,
                                                         0.5f, 0.75f, 0.5f, 0.5f, 0.75f}},
                                Texture::Encoding::Linear);
  textured.metallicRoughness =
      std::make_shared<Texture>(Image{1, 1, 3, {0.0f, 0.5f, 0.5f}}, Texture::Encoding::Linear);
  EXPECT_EQ(textured.at({0.3, 0.8}), plain);

  TriangleMesh floor = makeFloor(5, 0, "floor");
  for (const Vec3 &p : floor.positions) floor.uvs.push_back({p.x / 10 + 0.5, p.z / 10 + 0.5});
  const CameraSettings view{{0, 2, 3}, {0, 0, 0}, {0, 1, 0}, 40, false};
  RenderSettings s{8, 8, 16, IntegratorKind::Path, 3, 1000};
  const auto renderWith = [&](bool withTexture) {
    Scene scene = test::sceneWith({floor}, {std::make_shared<DisneyBrdf>(plain)},
                                  test::constantMap(1.0f), view);
    if (withTexture) {
      scene.materials[0] = std::make_shared<DisneyBrdf>(textured.factors);
      scene.textured = {std::make_shared<const TexturedDisney>(textured)};
    }
    auto backend = makeBackend("sobol", 2);
    return render(scene, s, *backend);
  };
  const Image a = renderWith(false), b = renderWith(true);
  for (std::size_t i = 0; i < a.pixels.size(); ++i) EXPECT_NEAR(a.pixels[i], b.pixels[i], 1e-6);
}

}  // namespace
}  // namespace nuld
