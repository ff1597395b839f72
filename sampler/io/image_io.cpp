#include "sampler/io/image_io.h"

#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "sampler/io/atomic_file.h"
#include "sampler/io/image_codec.h"
#include "sampler/io/input_file.h"
#include "sampler/plugin.h"
#include "sampler/resources.h"

namespace nuld {

const ImageCodec &imageCodec() {
  return *static_cast<const ImageCodec *>(
      loadPlugin({"libnuld_image.so", "NULD_IMAGE_PLUGIN", "nuld_image_codec", kImageCodecVersion,
                  "reading or writing an image"}));
}

double Image::luminance(int x, int y) const {
  if (channels < 3) return at(x, y, 0);
  return rec709Luminance(at(x, y, 0), at(x, y, 1), at(x, y, 2));
}

ImageEncoding imageEncoding(const std::string &path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char &c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".exr" || ext == ".hdr" || ext == ".pfm") return ImageEncoding::Linear;
  if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") return ImageEncoding::Display;
  return ImageEncoding::Unknown;
}

namespace {

// Refuses a header without pixels or larger than memory allows, before
// anything is allocated: a corrupt or hostile one may claim far more than
// the file holds.
void checkImageHeader(const std::string &name, const Image &header) {
  if (header.width <= 0 || header.height <= 0 || header.channels <= 0)
    throw std::runtime_error(name + ": image has no pixels");
  requireMemory(double(header.width) * header.height * header.channels * sizeof(float),
                name + ": a " + std::to_string(header.width) + " x " +
                    std::to_string(header.height) + " image of " + std::to_string(header.channels) +
                    " channels");
}

void requireFinitePixels(const std::string &name, const Image &img) {
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < img.channels; ++c)
        if (!std::isfinite(img.at(x, y, c)))
          throw std::runtime_error(name + ": pixel (" + std::to_string(x) + ", " +
                                   std::to_string(y) + ") channel " + std::to_string(c) +
                                   " is not a finite number");
}

}  // namespace

Image readImage(const std::string &path, bool requireFinite) {
  requireInputFile(path, "image file");
  const Image img =
      imageCodec().read(path, [&](const Image &header) { checkImageHeader(path, header); });
  if (requireFinite) requireFinitePixels(path, img);
  return img;
}

Image readImageBytes(const std::string &name, std::span<const unsigned char> bytes) {
  if (bytes.empty()) throw std::runtime_error(name + ": the image holds no bytes");
  const Image img = imageCodec().readMemory(
      name, bytes, [&](const Image &header) { checkImageHeader(name, header); });
  requireFinitePixels(name, img);
  return img;
}

namespace {

// The image written to `file`'s temporary name and read back, before it
// takes its name: a codec that lost bytes without saying so (a full disk
// under a buffered writer) is caught here. An EXR holds the floats exactly;
// an 8-bit picture only its size. Compared bit for bit: a test's NaN
// pixel reads back as the same NaN.
void writeChecked(const AtomicFile &file, const Image &image, const ImageAttributes &attributes) {
  const std::string path = file.destination().string();
  // The temporary file keeps the extension: the codec picks the format by it.
  imageCodec().write(path, file.tempPath(), image, attributes);
  Image back;
  try {
    back = imageCodec().read(file.tempPath(), [](const Image &) {});
  } catch (const std::exception &) {
    throw std::runtime_error(path +
                             ": cannot write the image (it does not read back whole: is the "
                             "disk full?)");
  }
  const bool exact = file.destination().extension() == ".exr";
  if (back.width != image.width || back.height != image.height || back.channels != image.channels ||
      (exact && (back.pixels.size() != image.pixels.size() ||
                 std::memcmp(back.pixels.data(), image.pixels.data(),
                             image.pixels.size() * sizeof(float)) != 0)))
    throw std::runtime_error(path + ": cannot write the image (it reads back differently)");
}

}  // namespace

void writeImage(const std::string &path, const Image &image, const ImageAttributes &attributes) {
  AtomicFile file(path);
  writeChecked(file, image, attributes);
  file.commit();
}

void writeImagePair(const std::string &pathA, const Image &imageA, const std::string &pathB,
                    const Image &imageB, const ImageAttributes &attributes) {
  AtomicFile a(pathA), b(pathB);
  writeChecked(a, imageA, attributes);
  writeChecked(b, imageB, attributes);
  a.commit();
  b.commit();
}

ImageAttributes readImageAttributes(const std::string &path, const std::string &prefix) {
  requireInputFile(path, "image");
  return imageCodec().attributes(path, prefix);
}

}  // namespace nuld
