#pragma once
// Shared by the fuzz harnesses (tests/fuzz/README.md). The readers take
// paths, so each input is written to a scratch file first. A reader may
// accept an input or refuse it with an exception whose message names the
// file, as every reader promises; anything else is a finding: a crash, a
// sanitizer report, a hang, std::bad_alloc (a size in the input that should
// have been checked against the file's length), or a refusal that does not
// say which file it is about.

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <string>
#include <string_view>
#include <vector>

namespace nuld::fuzz {

[[noreturn]] inline void finding(const std::string &what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what.c_str());
  std::abort();
}

// A scratch file per process and extension, rewritten for every input and
// removed when the process exits normally.
class ScratchFile {
 public:
  explicit ScratchFile(const std::string &extension) {
    const std::filesystem::path shm("/dev/shm");
    const auto dir =
        std::filesystem::is_directory(shm) ? shm : std::filesystem::temp_directory_path();
    path_ = (dir / ("nuld_fuzz_" + std::to_string(::getpid()) + extension)).string();
  }
  ~ScratchFile() {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  ScratchFile(const ScratchFile &) = delete;
  ScratchFile &operator=(const ScratchFile &) = delete;

  const std::string &write(const std::uint8_t *data, std::size_t size) const {
    std::ofstream(path_, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char *>(data), std::streamsize(size));
    return path_;
  }
  const std::string &path() const { return path_; }

 private:
  std::string path_;
};

// Runs `read()`; a refusal must name one of `names` (the file, or the folder
// of the files it refers to).
template <class Read>
void readOrRefuse(const std::vector<std::string> &names, Read &&read) {
  try {
    read();
  } catch (const std::bad_alloc &) {
    finding("std::bad_alloc: an input size was not checked before allocating");
  } catch (const std::exception &e) {
    const std::string_view message = e.what();
    for (const std::string &name : names)
      if (message.find(name) != std::string_view::npos) return;
    finding("a refusal that names no file: " + std::string(message));
  }
}

}  // namespace nuld::fuzz
