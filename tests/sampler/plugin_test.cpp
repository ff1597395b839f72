// The plugin loader (sampler/plugin.h), against the image plugin of this
// build.

#include "sampler/plugin.h"

#include <gtest/gtest.h>

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

std::string refusal(const PluginSpec &spec) {
  try {
    loadPlugin(spec);
  } catch (const std::runtime_error &e) {
    return e.what();
  }
  return "";
}

TEST(Plugin, LoadsThePluginTheBuildMade) {
  const std::string built = imagePluginPath();
  ASSERT_TRUE(std::filesystem::exists(built)) << built;
  const void *codec = loadPlugin({"libnuld_image.so", "NULD_TEST_NO_SUCH_VARIABLE", built.c_str(),
                                  "nuld_image_codec", kImageCodecVersion, "a test"});
  EXPECT_EQ(codec, &imageCodec());  // the same object the image functions use
}

TEST(Plugin, AMissingPluginNamesEveryPlaceTried) {
  const std::string message = refusal({"libnuld_no_such.so", "NULD_TEST_NO_SUCH_VARIABLE",
                                       "/no/such/libnuld_no_such.so", "entry", 1, "the test"});
  EXPECT_NE(message.find("the test needs nuld's plugin libnuld_no_such.so"), std::string::npos)
      << message;
  EXPECT_NE(message.find("/no/such/libnuld_no_such.so: no such file"), std::string::npos);
  EXPECT_NE(message.find("tests/libnuld_no_such.so: no such file"), std::string::npos);
  EXPECT_NE(message.find("NULD_TEST_NO_SUCH_VARIABLE"), std::string::npos);
}

TEST(Plugin, AnotherBuildsOrAnotherLibraryIsRefusedByName) {
  const std::string built = imagePluginPath();
  const std::string version =
      refusal({"libnuld_no_such.so", "NULD_TEST_NO_SUCH_VARIABLE", built.c_str(),
               "nuld_image_codec", kImageCodecVersion + 1, "the test"});
  EXPECT_NE(
      version.find(built + ": built for interface version " + std::to_string(kImageCodecVersion) +
                   ", expected " + std::to_string(kImageCodecVersion + 1)),
      std::string::npos)
      << version;
  const std::string entry = refusal({"libnuld_no_such.so", "NULD_TEST_NO_SUCH_VARIABLE",
                                     built.c_str(), "nuld_no_such_entry", 1, "the test"});
  EXPECT_NE(entry.find(built + ": not the plugin (no nuld_no_such_entry)"), std::string::npos)
      << entry;
  // Not a shared library at all: dlopen's reason, after the file's name.
  const std::string source = std::string(NULD_SOURCE_DIR) + "/README.md";
  const std::string foreign = refusal(
      {"libnuld_no_such.so", "NULD_TEST_NO_SUCH_VARIABLE", source.c_str(), "entry", 1, "the test"});
  EXPECT_NE(foreign.find(source + ": "), std::string::npos) << foreign;
}

}  // namespace
}  // namespace nuld
