#pragma once
// The one way the project writes a file (docs/architecture.md, "Writes"):
// callers write to tempPath(), then commit() checks the temporary file to
// the disk (fsync) and renames it over the destination. Without commit()
// the temporary file is removed, so a failed, short or interrupted write
// never leaves a truncated file under a final name, and an earlier file of
// that name stays as it was.
//
// Every failure throws std::runtime_error naming the destination and the
// reason in the system's words ("No space left on device", "Read-only file
// system", "File too large").

#include <filesystem>
#include <string>

namespace nuld {

// The checks AtomicFile makes of a destination, without creating anything:
// it must be a regular file that is not read-only, or not exist (a link to
// a regular file is followed; the file it names is returned; a dangling
// link is refused, as GNU cp refuses to write through one), in a directory
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
  const std::filesystem::path &destination() const { return destination_; }
  // Flushes the temporary file to the disk, renames it over the destination
  // and flushes the directory: a file a later run trusts (a cache entry, a
  // checkpoint) is on the disk when commit returns.
  void commit();

 private:
  std::filesystem::path destination_, temp_;
  bool committed_ = false;
};

// Writes `contents` to `path` atomically, every write and the close checked.
void writeFileAtomically(const std::filesystem::path &path, const std::string &contents);

// Copies `from` to `to` atomically: a hard link where `link` is set and the
// file system allows one (the same bytes, no space taken), else a checked
// copy. A failure names `to`, the file that could not be written.
void copyFileAtomically(const std::filesystem::path &from, const std::filesystem::path &to,
                        bool link = false);

// "PATH: cannot write the file (No space left on device)": the message of a
// failed write, close or sync of `path`, with errno's text.
[[noreturn]] void throwWriteError(const std::filesystem::path &path, int error);

}  // namespace nuld
