#include "sampler/io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace nuld {

namespace {

// A file its owner made read-only is kept (a rename would replace it even
// so, and root's writes ignore the mode).
std::filesystem::path writable(const std::filesystem::path &file, std::filesystem::perms mode) {
  using std::filesystem::perms;
  if ((mode & (perms::owner_write | perms::group_write | perms::others_write)) == perms::none)
    throw std::runtime_error(file.string() + ": is read-only; refusing to replace it");
  return file;
}

// Refuses a destination that exists and is not a regular file: a rename
// would replace a device, a pipe or a socket by a plain file (and cannot
// replace a directory). A link to a regular file is followed, so the file it
// names is replaced and the link stays; a dangling link is refused (a rename
// would replace the link by a file, which its maker did not ask for).
std::filesystem::path regularDestination(std::filesystem::path destination) {
  std::error_code ec;
  const auto link = std::filesystem::symlink_status(destination, ec);
  if (ec || !std::filesystem::exists(link)) return destination;
  if (std::filesystem::is_symlink(link)) {
    const auto target = std::filesystem::status(destination, ec);
    if (ec || !std::filesystem::exists(target))
      throw std::runtime_error(destination.string() + ": is a dangling symbolic link (to " +
                               std::filesystem::read_symlink(destination, ec).string() +
                               "); refusing to write through it");
    if (!std::filesystem::is_regular_file(target))
      throw std::runtime_error(destination.string() +
                               ": names a link to something that is not a regular file; "
                               "refusing to write over it");
    return writable(std::filesystem::canonical(destination), target.permissions());
  }
  if (!std::filesystem::is_regular_file(link))
    throw std::runtime_error(
        destination.string() + ": exists and is not a regular file (" +
        (std::filesystem::is_directory(link) ? "a directory" : "a device, pipe or socket") +
        "); refusing to write over it");
  return writable(destination, link.permissions());
}

std::filesystem::path directoryOf(const std::filesystem::path &file) {
  return file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
}

// fsync(2) of `file`, then its close, both checked: a write the kernel
// accepted into its cache can still fail here (a full or remote disk).
void syncFile(const std::filesystem::path &file, const std::filesystem::path &named) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throwWriteError(named, errno);
  const int synced = ::fsync(fd) == 0 ? 0 : errno;
  const int closed = ::close(fd) == 0 ? 0 : errno;
  if (synced || closed) throwWriteError(named, synced ? synced : closed);
}

}  // namespace

void throwWriteError(const std::filesystem::path &path, int error) {
  throw std::runtime_error(path.string() + ": cannot write the file (" + std::strerror(error) +
                           ")");
}

std::filesystem::path checkDestination(const std::filesystem::path &destination) {
  std::filesystem::path checked = regularDestination(destination);
  const auto dir = directoryOf(checked);
  if (!std::filesystem::is_directory(dir))
    throw std::runtime_error(checked.string() + ": directory " + dir.string() + " does not exist");
  return checked;
}

AtomicFile::AtomicFile(std::filesystem::path destination)
    : destination_(checkDestination(destination)) {
  // Hidden, per-process name; built by appending (GCC 12 warns falsely on "." + string).
  std::string name = ".";
  name += destination_.stem().string();
  name += ".tmp" + std::to_string(::getpid());
  name += destination_.extension().string();
  temp_ = directoryOf(destination_) / name;
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

void AtomicFile::commit() {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(temp_, ec))
    throw std::runtime_error(destination_.string() + ": the file was not written");
  syncFile(temp_, destination_);
  regularDestination(destination_);  // it may have appeared since
  std::filesystem::rename(temp_, destination_, ec);
  if (ec)
    throw std::runtime_error(destination_.string() + ": cannot replace file (" + ec.message() +
                             ")");
  committed_ = true;
  // The rename itself reaches the disk with its directory. A directory that
  // cannot be opened or synced (some network file systems) leaves the file
  // as safe as the system keeps it.
  if (const int dir = ::open(directoryOf(destination_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
      dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
}

void writeFileAtomically(const std::filesystem::path &path, const std::string &contents) {
  AtomicFile file(path);
  const int fd = ::open(file.tempPath().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throwWriteError(file.destination(), errno);
  std::size_t written = 0;
  int error = 0;
  while (written < contents.size()) {
    const ssize_t n = ::write(fd, contents.data() + written, contents.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : ENOSPC;
      break;
    }
    written += std::size_t(n);
  }
  if (::close(fd) != 0 && !error) error = errno;
  if (error) throwWriteError(file.destination(), error);
  file.commit();
}

void copyFileAtomically(const std::filesystem::path &from, const std::filesystem::path &to,
                        bool link) {
  AtomicFile file(to);
  std::error_code ec;
  if (!link || (std::filesystem::create_hard_link(from, file.tempPath(), ec), ec)) {
    ec.clear();
    std::filesystem::copy_file(from, file.tempPath(),
                               std::filesystem::copy_options::overwrite_existing, ec);
    if (ec) throwWriteError(file.destination(), ec.value());
  }
  file.commit();
}

}  // namespace nuld
