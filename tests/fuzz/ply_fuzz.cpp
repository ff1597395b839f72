// Fuzzes the PLY loader (scenes/ply_loader.h): ascii and both binary
// byte orders, whichever the header names.

#include "scenes/ply_loader.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size) {
  static const nuld::fuzz::ScratchFile file(".ply");
  const std::string &path = file.write(data, size);
  nuld::fuzz::readOrRefuse({path}, [&] { nuld::loadPly(path); });
  return 0;
}
