// Fuzzes the glTF loader (scenes/gltf_loader.h): an input starting with the
// binary container's magic "glTF" is read as .glb, any other as .gltf JSON.

#include <cstring>

#include "scenes/gltf_loader.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size) {
  static const nuld::fuzz::ScratchFile glb(".glb"), gltf(".gltf");
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string &path = (binary ? glb : gltf).write(data, size);
  nuld::fuzz::readOrRefuse({path}, [&] { nuld::loadGltf(path); });
  return 0;
}
