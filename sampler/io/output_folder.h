#pragma once
// Folders a command fills with many files (a study's, a bank's). A command
// never overwrites or deletes a file it did not write (docs/usage.md,
// "Conventions worth knowing"), and a folder's files are not recorded one by
// one, so the rule is kept per folder: a command writes into a folder only if
// it made it, found it empty, or finds its own mark there (a rerun, a resumed
// run). The mark is a hidden file, .nuld-folder, whose one line names its owner
// ("study render", "bank"); readers of a folder skip hidden files.

#include <filesystem>
#include <string>

namespace nuld {

inline constexpr const char *kFolderMark = ".nuld-folder";

// Makes `dir` (and its parents) if it is missing and marks it as `owner`'s;
// accepts an empty folder or one `owner` marked. Throws
// std::invalid_argument naming the folder and one file in it when it holds
// anything else, or when another owner marked it.
void claimOutputFolder(const std::filesystem::path &dir, const std::string &owner);

// Throws std::invalid_argument unless `dir` is a folder `owner` marked (a
// command that only adds to a folder another run made, e.g. study report).
void requireOwnedFolder(const std::filesystem::path &dir, const std::string &owner);

}  // namespace nuld
