// Fuzzes the binary point-set format (sampler/io/pointset_io.h). The reader
// recognizes it by its 8-byte magic, which the harness puts in front of every
// input so that mutations explore the header and the data behind it.

#include <cstring>
#include <vector>

#include "sampler/io/pointset_io.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size) {
  static const nuld::fuzz::ScratchFile file(".ptsb");
  static constexpr char kMagic[8] = {'N', 'U', 'L', 'D', 'P', 'T', 'S', '1'};
  std::vector<std::uint8_t> bytes(kMagic, kMagic + sizeof kMagic);
  bytes.insert(bytes.end(), data, data + size);
  const std::string &path = file.write(bytes.data(), bytes.size());
  nuld::fuzz::readOrRefuse({path}, [&] { nuld::readPointSet(path); });
  return 0;
}
