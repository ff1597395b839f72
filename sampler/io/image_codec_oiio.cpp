// The image codec of the plugin libnuld_image.so (image_codec.h): the one
// translation unit that includes OpenImageIO.

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <memory>
#include <stdexcept>

#include "sampler/io/image_codec.h"

namespace nuld {
namespace {

// The file's reader. OpenImageIO's own wording names its internals, so its
// error is cleared and ours, `why`, says what to check.
std::unique_ptr<OIIO::ImageInput> openInput(const std::string &path, const char *why) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    OIIO::geterror();
    throw std::runtime_error(path + ": " + why);
  }
  return in;
}

// Every pixel of an open image as float, its size shown to `checkHeader`
// before anything is allocated.
Image decode(const std::string &name, std::unique_ptr<OIIO::ImageInput> in,
             const std::function<void(const Image &)> &checkHeader) {
  const OIIO::ImageSpec &spec = in->spec();
  Image img;
  img.width = spec.width;
  img.height = spec.height;
  img.channels = spec.nchannels;
  checkHeader(img);
  img.pixels.resize(std::size_t(img.width) * img.height * img.channels);
  if (!in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.pixels.data())) {
    OIIO::geterror();
    throw std::runtime_error(name + ": cannot decode the image data (a truncated or damaged file)");
  }
  in->close();
  return img;
}

class OiioCodec final : public ImageCodec {
 public:
  Image read(const std::string &path,
             const std::function<void(const Image &)> &checkHeader) const override {
    return decode(path,
                  openInput(path,
                            "cannot read it as an image (a format OpenImageIO does not read, "
                            "or a damaged file)"),
                  checkHeader);
  }

  Image readMemory(const std::string &name, std::span<const unsigned char> bytes,
                   const std::function<void(const Image &)> &checkHeader) const override {
    // OpenImageIO reads through the proxy only while it lives. The reader
    // is made by the format's name and given the proxy before it opens:
    // open(name, config, proxy) looks for a file of that name instead.
    OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
    const std::string format = std::filesystem::path(name).extension().string();
    auto in = format.size() > 1 ? OIIO::ImageInput::create(format.substr(1)) : nullptr;
    OIIO::ImageSpec spec;
    if (!in || !in->supports("ioproxy") || !(in->set_ioproxy(&proxy), in->open(name, spec))) {
      OIIO::geterror();
      throw std::runtime_error(name +
                               ": cannot read it as an image (not a PNG or JPEG "
                               "OpenImageIO can decode, or damaged data)");
    }
    return decode(name, std::move(in), checkHeader);
  }

  void write(const std::string &path, const std::string &file, const Image &image,
             const ImageAttributes &attributes) const override {
    auto out = OIIO::ImageOutput::create(file);
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
    if (!out->open(file, spec))
      throw std::runtime_error(path + ": cannot open " + file +
                               " for writing (is the directory writable?)");
    // The close writes what the codec buffered (a PNG's last rows, an EXR's
    // offset table): a failure there is a truncated file too.
    if (!out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()) || !out->close()) {
      OIIO::geterror();
      throw std::runtime_error(path + ": cannot write the image (is the disk full?)");
    }
  }

  ImageAttributes attributes(const std::string &path, const std::string &prefix) const override {
    const auto in = openInput(path, "cannot read the image's header");
    ImageAttributes out;
    for (const OIIO::ParamValue &p : in->spec().extra_attribs)
      if (p.type() == OIIO::TypeDesc::STRING && p.name().string().rfind(prefix, 0) == 0)
        out.emplace_back(p.name().string(), p.get_string());
    return out;
  }
};

}  // namespace
}  // namespace nuld

extern "C" const void *nuld_image_codec(int *version) {
  static const nuld::OiioCodec codec;
  *version = nuld::kImageCodecVersion;
  return &codec;
}
