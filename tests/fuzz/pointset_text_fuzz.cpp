// Fuzzes the text point-set format (sampler/io/pointset_io.h).

#include "sampler/io/pointset_io.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size) {
  static const nuld::fuzz::ScratchFile file(".txt");
  const std::string &path = file.write(data, size);
  nuld::fuzz::readOrRefuse({path}, [&] { nuld::readPointSet(path); });
  return 0;
}
