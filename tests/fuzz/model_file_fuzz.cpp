// Fuzzes the model file (sampler/neural/model_file.h) and the settings its
// metadata records (NeuralSettings::fromModelFile, which checks them before
// NeuralGenerator::load builds a network; no LibTorch). A file ends
// in a checksum of everything before it, which random mutations almost never
// keep; the harness rewrites it for inputs that start with the magic, so the
// fuzzer reaches the tensors and the metadata. (A wrong checksum is covered
// by tests/neural/model_file_test.cpp.)

#include <cstring>
#include <vector>

#include "sampler/neural/model_file.h"
#include "sampler/neural/neural_generator.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size) {
  static const nuld::fuzz::ScratchFile file(".nuldnet");
  std::vector<std::uint8_t> bytes(data, data + size);
  if (size >= 16 && std::memcmp(data, "NULDNET1", 8) == 0) {
    const std::uint64_t sum =
        nuld::modelFileChecksum(reinterpret_cast<const char *>(bytes.data()), size - 8);
    std::memcpy(bytes.data() + size - 8, &sum, 8);
  }
  const std::string &path = file.write(bytes.data(), bytes.size());
  nuld::fuzz::readOrRefuse(
      {path}, [&] { nuld::NeuralSettings::fromModelFile(nuld::readModelFile(path), path); });
  return 0;
}
