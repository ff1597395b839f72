#pragma once
// Writes a file atomically: callers write to tempPath(), then commit() renames
// it over the destination. Without commit() the temporary file is removed, so
// a failed or interrupted write never leaves a truncated output behind.

#include <filesystem>
#include <string>

namespace nuld {

// The checks AtomicFile makes of a destination, without creating anything:
// it must be a regular file that is not read-only, or not exist (a link to
// a regular file is followed; the file it names is returned), in a directory
// that exists.
// Commands with several outputs check them all first, so that none is
// written when another cannot be.
std::filesystem::path checkDestination(const std::filesystem::path &destination);

class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path destination);
  ~AtomicFile();
  AtomicFile(const AtomicFile &) = delete;
  AtomicFile &operator=(const AtomicFile &) = delete;

  // Same directory and extension as the destination, so rename is atomic and
  // format detection by extension still works.
  std::string tempPath() const { return temp_.string(); }
  void commit();

 private:
  std::filesystem::path destination_, temp_;
  bool committed_ = false;
};

// Convenience: writes `contents` to `path` atomically.
void writeFileAtomically(const std::filesystem::path &path, const std::string &contents);

}  // namespace nuld
