#pragma once
// The image formats, through OpenImageIO in a plugin (libnuld_image.so,
// sampler/plugin.h) that the first image read or write loads. image_io.h is
// what callers use; this is the line between it and the plugin.

#include <functional>
#include <span>
#include <string>

#include "sampler/io/image_io.h"

namespace nuld {

class ImageCodec {
 public:
  virtual ~ImageCodec() = default;
  // Every pixel of `path` as float. `checkHeader` sees the size (pixels
  // empty) before anything is allocated and throws to refuse it. Throws
  // std::runtime_error naming the file.
  virtual Image read(const std::string &path,
                     const std::function<void(const Image &header)> &checkHeader) const = 0;
  // The same for an image held in memory (a glTF file's embedded texture);
  // `name` says its format by its extension and names it in messages.
  virtual Image readMemory(const std::string &name, std::span<const unsigned char> bytes,
                           const std::function<void(const Image &header)> &checkHeader) const = 0;
  // Writes `image` to `file`, in the format of its extension, on behalf of
  // `path` (what messages name). Throws std::runtime_error naming `path`.
  virtual void write(const std::string &path, const std::string &file, const Image &image,
                     const ImageAttributes &attributes) const = 0;
  virtual ImageAttributes attributes(const std::string &path, const std::string &prefix) const = 0;
};

// Bumped whenever ImageCodec or Image changes.
inline constexpr int kImageCodecVersion = 2;

// The plugin's codec (loadPlugin; the variable is NULD_IMAGE_PLUGIN).
const ImageCodec &imageCodec();

}  // namespace nuld

// The plugin's one exported symbol (sampler/plugin.h).
extern "C" const void *nuld_image_codec(int *version);
