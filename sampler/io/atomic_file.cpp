#include "sampler/io/atomic_file.h"

#include <unistd.h>

#include <fstream>
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
// names is replaced and the link stays.
std::filesystem::path regularDestination(std::filesystem::path destination) {
  std::error_code ec;
  const auto link = std::filesystem::symlink_status(destination, ec);
  if (ec || !std::filesystem::exists(link)) return destination;
  if (std::filesystem::is_symlink(link)) {
    const auto target = std::filesystem::status(destination, ec);
    if (!ec && std::filesystem::exists(target)) {
      if (!std::filesystem::is_regular_file(target))
        throw std::runtime_error(destination.string() +
                                 ": names a link to something that is not a regular file; "
                                 "refusing to write over it");
      return writable(std::filesystem::canonical(destination), target.permissions());
    }
    return destination;  // a dangling link: the rename replaces the link itself
  }
  if (!std::filesystem::is_regular_file(link))
    throw std::runtime_error(
        destination.string() + ": exists and is not a regular file (" +
        (std::filesystem::is_directory(link) ? "a directory" : "a device, pipe or socket") +
        "); refusing to write over it");
  return writable(destination, link.permissions());
}

}  // namespace

std::filesystem::path checkDestination(const std::filesystem::path &destination) {
  std::filesystem::path checked = regularDestination(destination);
  const auto dir = checked.has_parent_path() ? checked.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(dir))
    throw std::runtime_error(checked.string() + ": directory " + dir.string() + " does not exist");
  return checked;
}

AtomicFile::AtomicFile(std::filesystem::path destination)
    : destination_(checkDestination(destination)) {
  const auto dir =
      destination_.has_parent_path() ? destination_.parent_path() : std::filesystem::path(".");
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
  regularDestination(destination_);  // it may have appeared since
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
