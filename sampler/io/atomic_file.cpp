#include "sampler/io/atomic_file.h"

#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <system_error>

namespace nuld {

AtomicFile::AtomicFile(std::filesystem::path destination) : destination_(std::move(destination)) {
  const auto dir =
      destination_.has_parent_path() ? destination_.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(dir))
    throw std::runtime_error(destination_.string() + ": directory " + dir.string() +
                             " does not exist");
  // Hidden, per-process name; built by appending (GCC 12 warns falsely on "." + string).
  std::string name = ".";
  name += destination_.stem().string();
  name += ".tmp" + std::to_string(::getpid());
  name += destination_.extension().string();
  temp_ = dir / name;
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

void AtomicFile::commit() {
  std::error_code ec;
  std::filesystem::rename(temp_, destination_, ec);
  if (ec)
    throw std::runtime_error(destination_.string() + ": cannot replace file (" + ec.message() +
                             ")");
  committed_ = true;
}

void writeFileAtomically(const std::filesystem::path &path, const std::string &contents) {
  AtomicFile file(path);
  {
    std::ofstream out(file.tempPath(), std::ios::binary);
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) throw std::runtime_error(path.string() + ": write failed");
  }
  file.commit();
}

}  // namespace nuld
