#pragma once
// An RGB image a material reads at a surface's texture coordinates (glTF
// textures: scenes/gltf_scene.h). Texels are linear; an 8-bit colour
// texture is decoded from sRGB once, when it is made (srgbToLinear,
// sampler/io/image_io.h). Lookups filter
// bilinearly between texel centres with glTF's wrap modes; (0, 0) is the
// image's top-left corner and v runs down its rows, as glTF's UVs do.

#include <cstdint>
#include <vector>

#include "materials/rgb.h"
#include "sampler/io/content_hash.h"
#include "sampler/io/image_io.h"
#include "sampler/point.h"

namespace nuld {

class Texture {
 public:
  enum class Wrap { Repeat, Clamp, Mirror };
  enum class Encoding { Linear, Srgb };

  // From an image of 1 to 4 channels: grey is spread over R, G and B; a
  // fourth channel (alpha) is not kept. Throws std::invalid_argument for an
  // image without pixels.
  Texture(const Image &image, Encoding encoding, Wrap wrapU = Wrap::Repeat,
          Wrap wrapV = Wrap::Repeat);

  int width() const { return width_; }
  int height() const { return height_; }
  // The filtered value at `uv`; any finite uv gives a finite value.
  Rgb lookup(Point2 uv) const;
  // Texel (x, y), linear.
  Rgb texel(int x, int y) const;
  void hashContent(ContentHash &h) const;

 private:
  int width_, height_;
  Wrap wrapU_, wrapV_;
  std::vector<float> rgb_;  // row-major, 3 floats per texel
};

}  // namespace nuld
