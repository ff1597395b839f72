#include "sampler/io/output_folder.h"

#include <fstream>
#include <stdexcept>

#include "sampler/io/atomic_file.h"

namespace nuld {

namespace fs = std::filesystem;

namespace {

// The owner `dir`'s mark names ("" when it has none).
std::string markOwner(const fs::path &dir) {
  std::ifstream in(dir / kFolderMark);
  std::string owner;
  if (in) std::getline(in, owner);
  return owner;
}

// One entry of `dir` other than its mark, or an empty path.
fs::path foreignEntry(const fs::path &dir) {
  std::error_code ec;
  for (const auto &entry : fs::directory_iterator(dir, ec))
    if (entry.path().filename() != kFolderMark) return entry.path();
  if (ec)
    throw std::invalid_argument(dir.string() + ": cannot list the folder (" + ec.message() + ")");
  return {};
}

std::string adoptHint(const fs::path &dir, const std::string &owner) {
  return "name a new or empty folder (one an earlier nuld " + owner +
         " made before folders were marked: write the line '" + owner + "' into " +
         (dir / kFolderMark).string() + " to keep using it)";
}

}  // namespace

void claimOutputFolder(const fs::path &dir, const std::string &owner) {
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(dir, ec)) && !fs::exists(dir, ec))
    throw std::invalid_argument(dir.string() + ": is a dangling symbolic link (to " +
                                fs::read_symlink(dir, ec).string() +
                                "); name a folder, or make the folder it names first");
  const auto status = fs::status(dir, ec);
  if (fs::exists(status)) {
    if (!fs::is_directory(status))
      throw std::invalid_argument(dir.string() + ": exists and is not a folder");
    const std::string marked = markOwner(dir);
    if (marked == owner) return;
    if (!marked.empty())
      throw std::invalid_argument(dir.string() + ": a folder nuld " + marked + " wrote; nuld " +
                                  owner + " writes only into its own folders: name another");
    if (const fs::path foreign = foreignEntry(dir); !foreign.empty())
      throw std::invalid_argument(dir.string() + ": holds files nuld " + owner +
                                  " did not write (e.g. " + foreign.filename().string() +
                                  "); it never overwrites them: " + adoptHint(dir, owner));
  } else {
    fs::create_directories(dir);
  }
  writeFileAtomically(dir / kFolderMark, owner + "\n");
}

void requireOwnedFolder(const fs::path &dir, const std::string &owner) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw std::invalid_argument(dir.string() + ": no such folder");
  if (!fs::is_directory(dir, ec)) throw std::invalid_argument(dir.string() + ": not a folder");
  if (markOwner(dir) != owner)
    throw std::invalid_argument(dir.string() + ": not a folder nuld " + owner +
                                " made (it has no mark " + kFolderMark + " of it); " +
                                adoptHint(dir, owner));
}

}  // namespace nuld
