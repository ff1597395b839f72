// Fuzzes scene files (scenes/scene_file.h): the JSON, every field's checks,
// and the meshes, materials and map they name under tests/fuzz/assets. A
// refusal names the scene file or the asset it is about.

#include "scenes/scene_file.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size) {
  static const nuld::fuzz::ScratchFile file(".json");
  const std::string &path = file.write(data, size);
  nuld::fuzz::readOrRefuse({path, NULD_FUZZ_ASSETS},
                           [&] { nuld::loadScene(path, NULD_FUZZ_ASSETS); });
  return 0;
}
