#pragma once
// Image files (through OpenImageIO, in a plugin: image_codec.h). Reading
// validates the pixels; writing goes through a temporary file and a rename,
// so a reader never sees a half-written image.

#include <cmath>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace nuld {

// Rec. 709 luminance of linear RGB: the one place its weights live.
inline double rec709Luminance(double r, double g, double b) {
  return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

// The sRGB transfer curve (IEC 61966-2-1) both ways, for values in [0, 1]:
// the one place it lives (display images, textures, FLIP).
inline double srgbToLinear(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}
inline double linearToSrgb(double v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
}

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> pixels;  // row-major, row 0 at the top, interleaved channels

  float &at(int x, int y, int c) { return pixels[(std::size_t(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const {
    return pixels[(std::size_t(y) * width + x) * channels + c];
  }
  // Rec. 709 luminance (the single channel of a grey image).
  double luminance(int x, int y) const;
};

// What a file's extension (in any case) says its pixels hold: linear
// radiance (.exr, .hdr, .pfm), display values (.png, .jpg, .jpeg: 8 bits,
// sRGB-encoded, clipped at 1), or unknown (any other).
enum class ImageEncoding { Linear, Display, Unknown };
ImageEncoding imageEncoding(const std::string &path);

// Throws std::runtime_error naming the file on failure. With `requireFinite`
// a NaN or infinite pixel is an error naming the pixel.
Image readImage(const std::string &path, bool requireFinite = true);
// The same for an image held in memory (PNG or JPEG: an embedded texture);
// `name` ("file.glb: image 2.png") names it in messages and its extension
// says the format.
Image readImageBytes(const std::string &name, std::span<const unsigned char> bytes);

// Text attributes an image file carries (EXR header attributes, PNG text
// chunks), so that a file says how it was made: name and value pairs, names
// prefixed "nuld:" by the caller.
using ImageAttributes = std::vector<std::pair<std::string, std::string>>;

// The format follows the extension (.exr, .png, .hdr, ...); 8-bit formats are
// written with the values clamped to [0, 1] (no tone mapping here).
// Atomic (atomic_file.h), and read back before it takes its name.
void writeImage(const std::string &path, const Image &image,
                const ImageAttributes &attributes = {});
// Two images as one write (a render's EXR and its PNG): both are written
// and read back before either takes its name, so a failure leaves neither.
void writeImagePair(const std::string &pathA, const Image &imageA, const std::string &pathB,
                    const Image &imageB, const ImageAttributes &attributes = {});

// The string attributes of an image file whose names start with `prefix`, in
// the file's order. Throws std::runtime_error naming the file.
ImageAttributes readImageAttributes(const std::string &path, const std::string &prefix = "nuld:");

}  // namespace nuld
