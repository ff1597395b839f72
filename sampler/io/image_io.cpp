#include "sampler/io/image_io.h"

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "sampler/io/atomic_file.h"
#include "sampler/io/input_file.h"
#include "sampler/resources.h"

namespace nuld {

double Image::luminance(int x, int y) const {
  if (channels < 3) return at(x, y, 0);
  return rec709Luminance(at(x, y, 0), at(x, y, 1), at(x, y, 2));
}

Image readImage(const std::string &path, bool requireFinite) {
  requireInputFile(path, "image file");
  auto in = OIIO::ImageInput::open(path);
  // OpenImageIO's own wording names its internals; ours says what to check.
  if (!in) {
    OIIO::geterror();  // clear it
    throw std::runtime_error(path +
                             ": cannot read it as an image (a format OpenImageIO does not read, "
                             "or a damaged file)");
  }
  const OIIO::ImageSpec &spec = in->spec();
  Image img;
  img.width = spec.width;
  img.height = spec.height;
  img.channels = spec.nchannels;
  if (img.width <= 0 || img.height <= 0 || img.channels <= 0)
    throw std::runtime_error(path + ": image has no pixels");
  // The header's size, before allocating: a corrupt or hostile one may claim
  // far more than the file holds.
  requireMemory(double(img.width) * img.height * img.channels * sizeof(float),
                path + ": a " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                    " image of " + std::to_string(img.channels) + " channels");
  img.pixels.resize(std::size_t(img.width) * img.height * img.channels);
  if (!in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
    throw std::runtime_error(path + ": cannot decode the image data (a truncated or damaged file)");
  in->close();
  if (requireFinite) {
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        for (int c = 0; c < img.channels; ++c)
          if (!std::isfinite(img.at(x, y, c)))
            throw std::runtime_error(path + ": pixel (" + std::to_string(x) + ", " +
                                     std::to_string(y) + ") channel " + std::to_string(c) +
                                     " is not a finite number");
  }
  return img;
}

void writeImage(const std::string &path, const Image &image, const ImageAttributes &attributes) {
  AtomicFile file(path);
  auto out = OIIO::ImageOutput::create(path);
  if (!out) {
    OIIO::geterror();  // clear it
    throw std::runtime_error(path +
                             ": cannot write an image with this extension (use .exr, or "
                             ".png for an 8-bit picture)");
  }
  OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::FLOAT);
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") spec.set_format(OIIO::TypeDesc::UINT8);
  if (ext == ".exr") spec.attribute("compression", "zip");
  for (const auto &[name, value] : attributes) spec.attribute(name, value);
  // OpenImageIO picks the format from the name it is given, so the temporary
  // file keeps the extension.
  if (!out->open(file.tempPath(), spec))
    throw std::runtime_error(path + ": cannot open " + file.tempPath() +
                             " for writing (is the directory writable?)");
  if (!out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()))
    throw std::runtime_error(path + ": cannot write the image (is the disk full?)");
  out->close();
  file.commit();
}

ImageAttributes readImageAttributes(const std::string &path, const std::string &prefix) {
  requireInputFile(path, "image");
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    OIIO::geterror();  // clear it
    throw std::runtime_error(path + ": cannot read the image's header");
  }
  ImageAttributes out;
  for (const OIIO::ParamValue &p : in->spec().extra_attribs)
    if (p.type() == OIIO::TypeDesc::STRING && p.name().string().rfind(prefix, 0) == 0)
      out.emplace_back(p.name().string(), p.get_string());
  return out;
}

}  // namespace nuld
