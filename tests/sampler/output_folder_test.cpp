// Output folders (sampler/io/output_folder.h): a command writes only into a
// folder it made, found empty or marked before; anything else is refused and
// left as it was.

#include "sampler/io/output_folder.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "tests/common/expect_error.h"
#include "tests/common/temp_dir.h"

namespace nuld {
namespace {

namespace fs = std::filesystem;

std::string contents(const fs::path &file) {
  std::ifstream in(file);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(OutputFolder, MakesMarksAndTakesBackItsOwnFolder) {
  const test::TempDir dir;
  const fs::path out = dir / "a" / "study";
  claimOutputFolder(out, "study");
  EXPECT_EQ(contents(out / kFolderMark), "study\n");
  std::ofstream(out / "render.csv") << "x\n";
  claimOutputFolder(out, "study");  // a rerun
  EXPECT_EQ(contents(out / "render.csv"), "x\n");
  requireOwnedFolder(out, "study");
  // An empty folder is taken as it is.
  fs::create_directories(dir / "empty");
  claimOutputFolder(dir / "empty", "bank");
  EXPECT_EQ(contents(dir / "empty" / kFolderMark), "bank\n");
}

TEST(OutputFolder, RefusesAFolderOfOtherFilesAndLeavesIt) {
  const test::TempDir dir;
  const fs::path out = dir / "proj";
  fs::create_directories(out / "plots");
  std::ofstream(out / "index.html") << "mine\n";
  const std::string message = test::errorMessage([&] { claimOutputFolder(out, "study"); });
  EXPECT_NE(message.find(out.string() + ": holds files nuld study did not write (e.g. "),
            std::string::npos)
      << message;
  EXPECT_NE(message.find(kFolderMark), std::string::npos) << message;  // how to adopt it
  EXPECT_FALSE(fs::exists(out / kFolderMark));
  EXPECT_EQ(contents(out / "index.html"), "mine\n");
  test::expectRefusalMentioning([&] { requireOwnedFolder(out, "study"); },
                                "not a folder nuld study made");
}

TEST(OutputFolder, RefusesAnotherOwnersFolderAndAFile) {
  const test::TempDir dir;
  claimOutputFolder(dir / "bank", "bank");
  test::expectRefusalMentioning([&] { claimOutputFolder(dir / "bank", "study"); },
                                "a folder nuld bank wrote");
  std::ofstream(dir / "file") << "x";
  test::expectRefusalMentioning([&] { claimOutputFolder(dir / "file", "study"); },
                                "exists and is not a folder");
  test::expectRefusalMentioning([&] { requireOwnedFolder(dir / "none", "study"); },
                                "none: no such folder");
  test::expectRefusalMentioning([&] { requireOwnedFolder(dir / "file", "study"); },
                                "file: not a folder");
}

}  // namespace
}  // namespace nuld
