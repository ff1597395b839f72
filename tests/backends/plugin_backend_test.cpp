// plugin:PATH[:ARGS]: a user's sampler loaded from a shared library built
// against plugins/nuld_sampler.h. The example plugin's points are uniform
// (chi-square) and deterministic; the test plugin's misbehaviour (a NaN, a 1,
// a failed fill, a refusal, no entry, another version) is refused in words;
// pairs the plugin leaves are sobol's.

#include "backends/plugin_backend.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "backends/backend_registry.h"
#include "tests/common/chi_square.h"
#include "tests/common/expect_error.h"

namespace nuld {
namespace {

const std::string kExample = NULD_EXAMPLE_PLUGIN;
std::string testPlugin(const std::string &variant) {
  return std::string(NULD_TEST_PLUGIN_DIR) + "/libnuld_test_sampler_" + variant + ".so";
}

SamplingTargets image(std::uint32_t width, std::uint32_t height, std::uint32_t pairs = 4) {
  SamplingTargets t;
  t.width = width, t.height = height, t.pairs = pairs;
  return t;
}

TEST(PluginBackend, TheExamplesPointsAreUniformAndAPureFunction) {
  auto b = makeBackend("plugin:" + kExample, 3);
  b->prepare(16, image(40, 30));
  constexpr int kBins = 8;
  std::vector<double> observed(kBins * kBins, 0);
  std::vector<Point2> set(16), again(16);
  for (std::uint64_t pixel = 0; pixel < 1200; pixel += 3)
    for (std::uint32_t pair = 0; pair < 4; ++pair) {
      b->primary(pixel, pair, set);
      b->primary(pixel, pair, again);
      EXPECT_EQ(set, again);
      for (const Point2 &p : set) ++observed[int(p.y * kBins) * kBins + int(p.x * kBins)];
    }
  const double total = 400 * 4 * 16;
  const std::vector<double> expected(kBins * kBins, total / (kBins * kBins));
  EXPECT_GT(test::pooledChiSquare(observed, expected).pValue, 1e-4);
  // Another seed, other points.
  auto other = makeBackend("plugin:" + kExample, 4);
  other->prepare(16, image(40, 30));
  other->primary(0, 0, again);
  b->primary(0, 0, set);
  EXPECT_NE(set, again);
}

TEST(PluginBackend, BadPointsAndFailedFillsAreRefusedNamingThePixelAndPair) {
  for (const std::string mode : {"nan", "one", "negative"}) {
    auto b = makeBackend("plugin:" + testPlugin("ok") + ":" + mode, 1);
    b->prepare(4, image(8, 8));
    std::vector<Point2> out(4);
    b->primary(10, 0, out);  // pair 0 is fine
    const std::string message =
        test::errorMessage<std::runtime_error>([&] { b->primary(10, 1, out); });
    EXPECT_NE(message.find("expected points in [0, 1)^2"), std::string::npos) << message;
    EXPECT_NE(message.find("pixel (2, 1)"), std::string::npos) << message;
    EXPECT_NE(message.find("bounce 0's light"), std::string::npos) << message;
  }
  auto failing = makeBackend("plugin:" + testPlugin("ok") + ":fail", 1);
  failing->prepare(4, image(8, 8));
  std::vector<Point2> out(4);
  EXPECT_NE(test::errorMessage<std::runtime_error>([&] {
              failing->primary(0, 0, out);
            }).find("fill returned 7"),
            std::string::npos);
}

TEST(PluginBackend, ARefusalIsTheBackendsWithThePluginsReason) {
  auto b = makeBackend("plugin:" + testPlugin("ok") + ":refuse", 1);
  const std::string message =
      test::errorMessage<BackendRefusal>([&] { b->prepare(4, image(8, 8)); });
  EXPECT_NE(message.find("refuses on purpose"), std::string::npos) << message;
}

TEST(PluginBackend, AFileThatIsNotAPluginOfThisVersionIsRefusedInWords) {
  const auto refusal = [](const std::string &path) {
    return test::errorMessage<std::runtime_error>([&] { makeBackend("plugin:" + path, 1); });
  };
  EXPECT_NE(refusal(testPlugin("no_entry")).find("no nuld_sampler_entry"), std::string::npos);
  const std::string version = refusal(testPlugin("version99"));
  EXPECT_NE(version.find("version 99, expected 1"), std::string::npos) << version;
  EXPECT_NE(version.find("rebuild it against"), std::string::npos) << version;
  EXPECT_NE(refusal("/no/such/plugin.so").find("no such file"), std::string::npos);
  EXPECT_NE(refusal(NULD_SOURCE_DIR "/README.md").find("the sampler plugin"), std::string::npos);
  test::expectRefusalMentioning([] { makeBackend("plugin:", 1); }, "plugin:PATH[:ARGS]");
}

TEST(PluginBackend, ThePairsThePluginLeavesAreSobols) {
  auto b = makeBackend("plugin:" + testPlugin("ok") + ":camera", 5);
  auto sobol = makeBackend("sobol", 5);
  b->prepare(8, image(8, 8, 7));
  sobol->prepare(8, image(8, 8, 7));
  EXPECT_NE(b->report().note.find("the first 1 of the 7 pairs"), std::string::npos)
      << b->report().note;
  std::vector<Point2> got(8), want(8);
  for (std::uint32_t pair = 1; pair < 7; ++pair) {
    b->primary(9, pair, got);
    sobol->primary(9, pair, want);
    EXPECT_EQ(got, want) << "pair " << pair;
  }
  b->primary(9, 0, got);
  sobol->primary(9, 0, want);
  EXPECT_NE(got, want);
}

}  // namespace
}  // namespace nuld
