#pragma once
// The on-disk form of a trained generator (and of training checkpoints): text
// metadata plus named float32 tensors, closed by a checksum, so a truncated,
// corrupted or foreign file is an error that names the file and what is wrong
// instead of a crash or silent garbage. Nothing here depends on LibTorch.
//
// Layout (little-endian):
//   "NULDNET1"                      8-byte magic
//   uint32 metadataBytes, then that many bytes of "key=value\n" lines
//   uint32 tensorCount, then per tensor:
//     uint32 nameBytes, name, uint32 rank, rank x int64 dims, float32 data
//   uint64 FNV-1a hash of every byte before it

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace nuld {

struct ModelTensor {
  std::string name;
  std::vector<std::int64_t> shape;
  std::vector<float> data;  // row-major, product(shape) entries
};

struct ModelFile {
  std::map<std::string, std::string> metadata;
  std::vector<ModelTensor> tensors;
  // The closing checksum readModelFile found (and verified); 0 for a model
  // not read from a file. It names the file's content: caches key by it.
  std::uint64_t checksum = 0;

  const ModelTensor &tensor(const std::string &name, const std::string &path) const;
  // Throws naming the file and the key when it is missing.
  const std::string &value(const std::string &key, const std::string &path) const;
};

void writeModelFile(const std::string &path, const ModelFile &model);  // atomic
// The model in `path`, its checksum verified. The process keeps the last
// model read from each path and returns it again while the file keeps its
// size, modification time and closing checksum (8 bytes read), without
// reading and checksumming the rest: the renderer makes a neural backend
// per render and study repeat, and the byte-wise checksum of a whole model
// would be most of each one's cost (tools/experiments/neural_lobe_model.md,
// "Neural banks across processes", has the figures).
ModelFile readModelFile(const std::string &path);

// The file's closing checksum (FNV-1a, 64 bits) of `size` bytes: for tools
// that write model files by other means (the fuzz harness, tests/fuzz/).
std::uint64_t modelFileChecksum(const char *data, std::size_t size);
}  // namespace nuld
