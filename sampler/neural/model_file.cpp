#include "sampler/neural/model_file.h"

#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "sampler/io/atomic_file.h"
#include "sampler/io/input_file.h"

namespace nuld {
namespace {

static_assert(std::endian::native == std::endian::little, "model files are little-endian");

constexpr char kMagic[8] = {'N', 'U', 'L', 'D', 'N', 'E', 'T', '1'};
// Bounds that no real model reaches; beyond them the file is corrupt, and
// reading on would allocate absurd amounts.
constexpr std::uint32_t kMaxMetadataBytes = 1u << 20;
constexpr std::uint32_t kMaxTensors = 1024;
constexpr std::uint32_t kMaxRank = 8;
constexpr std::int64_t kMaxElements = std::int64_t(1) << 31;

template <class T>
void put(std::string &out, T v) {
  out.append(reinterpret_cast<const char *>(&v), sizeof v);
}

// Reads from the in-memory file; every failure names the file and the part.
class Reader {
 public:
  Reader(const std::string &path, const std::string &bytes) : path_(path), bytes_(bytes) {}

  template <class T>
  T get(const std::string &what) {
    T v;
    std::memcpy(&v, take(sizeof v, what), sizeof v);
    return v;
  }
  const char *take(std::size_t n, const std::string &what) {
    if (n > bytes_.size() - pos_) fail("truncated while reading " + what);
    const char *p = bytes_.data() + pos_;
    pos_ += n;
    return p;
  }
  [[noreturn]] void fail(const std::string &why) const {
    throw std::runtime_error(path_ + ": " + why + " (at byte " + std::to_string(pos_) + ")");
  }
  std::size_t position() const { return pos_; }

 private:
  const std::string &path_, &bytes_;
  std::size_t pos_ = 0;
};

}  // namespace

const ModelTensor &ModelFile::tensor(const std::string &name, const std::string &path) const {
  for (const ModelTensor &t : tensors)
    if (t.name == name) return t;
  throw std::runtime_error(path + ": model has no tensor '" + name + "'");
}

const std::string &ModelFile::value(const std::string &key, const std::string &path) const {
  const auto it = metadata.find(key);
  if (it == metadata.end()) throw std::runtime_error(path + ": model metadata lacks '" + key + "'");
  return it->second;
}

std::uint64_t modelFileChecksum(const char *data, std::size_t size) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::size_t i = 0; i < size; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= 0x100000001b3ull;
  }
  return h;
}

void writeModelFile(const std::string &path, const ModelFile &model) {
  std::string out(kMagic, sizeof kMagic);
  std::string meta;
  for (const auto &[k, v] : model.metadata) {
    if (k.find_first_of("=\n") != std::string::npos || v.find('\n') != std::string::npos)
      throw std::invalid_argument("model metadata '" + k + "' contains '=' or a newline");
    meta += k + "=" + v + "\n";
  }
  put(out, std::uint32_t(meta.size()));
  out += meta;
  put(out, std::uint32_t(model.tensors.size()));
  for (const ModelTensor &t : model.tensors) {
    std::int64_t count = 1;
    for (std::int64_t d : t.shape) count *= d;
    if (count != std::int64_t(t.data.size()))
      throw std::invalid_argument("model tensor '" + t.name + "': shape and data disagree");
    put(out, std::uint32_t(t.name.size()));
    out += t.name;
    put(out, std::uint32_t(t.shape.size()));
    for (std::int64_t d : t.shape) put(out, d);
    out.append(reinterpret_cast<const char *>(t.data.data()), t.data.size() * sizeof(float));
  }
  put(out, modelFileChecksum(out.data(), out.size()));
  writeFileAtomically(path, out);
}

namespace {

// What identifies a model file's content without reading it all: its size,
// modification time and closing checksum (which any change to the content
// changes, FNV-1a over every byte before it).
struct FileStamp {
  std::uintmax_t size = 0;
  std::filesystem::file_time_type modified;
  std::uint64_t checksum = 0;
  bool operator==(const FileStamp &) const = default;
};

std::optional<FileStamp> stampOf(const std::string &path) {
  std::error_code ec;
  FileStamp s;
  s.size = std::filesystem::file_size(path, ec);
  if (ec || s.size < sizeof kMagic + 8) return std::nullopt;
  s.modified = std::filesystem::last_write_time(path, ec);
  if (ec) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  in.seekg(std::streamoff(s.size - 8));
  if (!in.read(reinterpret_cast<char *>(&s.checksum), 8)) return std::nullopt;
  return s;
}

ModelFile readWholeModelFile(const std::string &path);

}  // namespace

ModelFile readModelFile(const std::string &path) {
  requireInputFile(path, "the model file");
  static std::mutex mutex;
  static std::map<std::string, std::pair<FileStamp, ModelFile>> read;
  const auto stamp = stampOf(path);
  if (stamp) {
    const std::lock_guard lock(mutex);
    if (const auto it = read.find(path); it != read.end() && it->second.first == *stamp)
      return it->second.second;
  }
  ModelFile model = readWholeModelFile(path);
  // Kept only when the file did not change while it was read.
  if (stamp && model.checksum == stamp->checksum && stampOf(path) == stamp) {
    const std::lock_guard lock(mutex);
    read[path] = {*stamp, model};
  }
  return model;
}

namespace {

ModelFile readWholeModelFile(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open the model file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string bytes = buffer.str();
  Reader r(path, bytes);

  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw std::runtime_error(path + ": not a nuld model file (expected the magic 'NULDNET1')");
  r.take(sizeof kMagic, "the magic");
  // Check the whole file before interpreting sizes inside it.
  if (bytes.size() < sizeof kMagic + 8) r.fail("truncated: no checksum");
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  if (modelFileChecksum(bytes.data(), bytes.size() - 8) != stored)
    throw std::runtime_error(path +
                             ": checksum mismatch (the model file is truncated or corrupted)");

  ModelFile model;
  model.checksum = stored;
  const auto metaBytes = r.get<std::uint32_t>("the metadata size");
  if (metaBytes > kMaxMetadataBytes) r.fail("implausible metadata size");
  std::istringstream meta(std::string(r.take(metaBytes, "the metadata"), metaBytes));
  for (std::string line; std::getline(meta, line);) {
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) r.fail("metadata line " + quotedInput(line) + " is not key=value");
    model.metadata[line.substr(0, eq)] = line.substr(eq + 1);
  }
  const auto count = r.get<std::uint32_t>("the tensor count");
  if (count > kMaxTensors) r.fail("implausible tensor count " + std::to_string(count));
  for (std::uint32_t k = 0; k < count; ++k) {
    ModelTensor t;
    const auto nameBytes = r.get<std::uint32_t>("a tensor name size");
    if (nameBytes > 256) r.fail("implausible tensor name size");
    t.name.assign(r.take(nameBytes, "a tensor name"), nameBytes);
    const auto rank = r.get<std::uint32_t>("the rank of " + quotedInput(t.name));
    if (rank > kMaxRank) r.fail("tensor '" + t.name + "' has implausible rank");
    std::int64_t elements = 1;
    for (std::uint32_t d = 0; d < rank; ++d) {
      const auto dim = r.get<std::int64_t>("a dimension of " + quotedInput(t.name));
      if (dim < 0 || dim > kMaxElements || elements * std::max<std::int64_t>(dim, 1) > kMaxElements)
        r.fail("tensor '" + t.name + "' has an implausible shape");
      elements *= dim;
      t.shape.push_back(dim);
    }
    // Taken before allocating: a header may declare far more than the file holds.
    const auto *data =
        r.take(std::size_t(elements) * sizeof(float), "the data of " + quotedInput(t.name));
    t.data.resize(std::size_t(elements));
    // An empty tensor has no storage: memcpy to its null data() is undefined
    // even for 0 bytes (UBSan, tools/sanitize.sh).
    if (!t.data.empty()) std::memcpy(t.data.data(), data, t.data.size() * sizeof(float));
    model.tensors.push_back(std::move(t));
  }
  if (r.position() != bytes.size() - 8) r.fail("unexpected bytes after the last tensor");
  return model;
}

}  // namespace

}  // namespace nuld
