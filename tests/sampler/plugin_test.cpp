// The plugin loader (sampler/plugin.h), against the image plugin of this
// build.

#include "sampler/plugin.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "sampler/io/image_codec.h"

namespace nuld {
namespace {

// The build root, where the plugins are: this program is in BUILD/tests.
std::string imagePluginPath() {
  return (std::filesystem::read_symlink("/proc/self/exe").parent_path().parent_path() /
          "libnuld_image.so")
      .string();
}

constexpr const char *kVariable = "NULD_TEST_PLUGIN";

// The loader's refusal of `file`, with kVariable naming `named` (unset when empty).
std::string refusal(const char *file, const std::string &named, const char *entry, int version) {
  if (named.empty())
    unsetenv(kVariable);
  else
    setenv(kVariable, named.c_str(), 1);
  std::string message;
  try {
    loadPlugin({file, kVariable, entry, version, "the test"});
  } catch (const std::runtime_error &e) {
    message = e.what();
  }
  unsetenv(kVariable);
  return message;
}

TEST(Plugin, LoadsThePluginTheBuildMade) {
  const std::string built = imagePluginPath();
  ASSERT_TRUE(std::filesystem::exists(built)) << built;
  unsetenv(kVariable);  // found in the build root, where the build wrote it
  const void *codec =
      loadPlugin({"libnuld_image.so", kVariable, "nuld_image_codec", kImageCodecVersion, "a test"});
  EXPECT_EQ(codec, &imageCodec());  // the same object the image functions use
}

TEST(Plugin, AMissingPluginNamesEveryPlaceTried) {
  const std::string message =
      refusal("libnuld_no_such.so", "/no/such/libnuld_no_such.so", "entry", 1);
  EXPECT_NE(message.find("the test needs nuld's plugin libnuld_no_such.so"), std::string::npos)
      << message;
  EXPECT_NE(message.find("/no/such/libnuld_no_such.so: no such file"), std::string::npos);
  EXPECT_NE(message.find("tests/libnuld_no_such.so: no such file"), std::string::npos);
  const std::string root = std::filesystem::path(imagePluginPath()).parent_path().string();
  EXPECT_NE(message.find(root + "/libnuld_no_such.so: no such file"), std::string::npos);
  EXPECT_NE(message.find(kVariable), std::string::npos);
}

TEST(Plugin, AnotherBuildsOrAnotherLibraryIsRefusedByName) {
  const std::string built = imagePluginPath();
  const std::string version =
      refusal("libnuld_no_such.so", built, "nuld_image_codec", kImageCodecVersion + 1);
  EXPECT_NE(
      version.find(built + ": built for interface version " + std::to_string(kImageCodecVersion) +
                   ", expected " + std::to_string(kImageCodecVersion + 1)),
      std::string::npos)
      << version;
  const std::string entry = refusal("libnuld_no_such.so", built, "nuld_no_such_entry", 1);
  EXPECT_NE(entry.find(built + ": not the plugin (no nuld_no_such_entry)"), std::string::npos)
      << entry;
  // Not a shared library at all: dlopen's reason, after the file's name.
  const std::string source = std::string(NULD_SOURCE_DIR) + "/README.md";
  const std::string foreign = refusal("libnuld_no_such.so", source, "entry", 1);
  EXPECT_NE(foreign.find(source + ": "), std::string::npos) << foreign;
}

}  // namespace
}  // namespace nuld
