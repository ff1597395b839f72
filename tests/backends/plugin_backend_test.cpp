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

SamplingTargets image(std::uint32_t width, std::uint32_t height, int bounces = 1) {
  SamplingTargets t;
  t.width = width, t.height = height, t.domains = SampleLayout::domains(bounces);
  t.integrator = bounces > 1 ? "path" : "direct";
  return t;
}

TEST(PluginBackend, TheExamplesPointsAreUniformAndAPureFunction) {
  auto b = makeBackend("plugin:" + kExample, 3);
  b->prepare(16, image(40, 30));
  constexpr int kBins = 8;
  std::vector<double> observed(kBins * kBins, 0);
  std::vector<Point2> set(16), again(16);
  for (std::uint64_t pixel = 0; pixel < 1200; pixel += 3)
    for (std::uint32_t pair : {SampleLayout::camera, SampleLayout::light(0), SampleLayout::bsdf(0),
                               SampleLayout::bsdf(0)}) {
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
    // Version 1's pair 1 is the light domain.
    const std::string message = test::errorMessage<std::runtime_error>(
        [&] { b->primary(10, SampleLayout::light(0), out); });
    EXPECT_NE(message.find("expected numbers in [0, 1)"), std::string::npos) << message;
    EXPECT_NE(message.find("version 1's pair 1"), std::string::npos) << message;
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
  EXPECT_NE(version.find("version 99, expected 1 to 2"), std::string::npos) << version;
  EXPECT_NE(version.find("rebuild it against"), std::string::npos) << version;
  EXPECT_NE(refusal("/no/such/plugin.so").find("no such file"), std::string::npos);
  EXPECT_NE(refusal(NULD_SOURCE_DIR "/README.md").find("the sampler plugin"), std::string::npos);
  test::expectRefusalMentioning([] { makeBackend("plugin:", 1); }, "plugin:PATH[:ARGS]");
}

TEST(PluginBackend, ThePairsThePluginLeavesAreSobols) {
  auto b = makeBackend("plugin:" + testPlugin("ok") + ":camera", 5);
  auto sobol = makeBackend("sobol", 5);
  b->prepare(8, image(8, 8, 2));
  sobol->prepare(8, image(8, 8, 2));
  EXPECT_NE(b->report().note.find("serves 1 of the 11 domains"), std::string::npos)
      << b->report().note;
  std::vector<Point2> got(8), want(8);
  std::vector<double> got1(8), want1(8);
  for (std::uint32_t domain = 1; domain < SampleLayout::domains(2); ++domain) {
    if (SampleLayout::dimensions(domain) == 2) {
      b->primary(9, domain, got);
      sobol->primary(9, domain, want);
      EXPECT_EQ(got, want) << "domain " << domain;
    } else {
      b->primary1D(9, domain, got1);
      sobol->primary1D(9, domain, want1);
      EXPECT_EQ(got1, want1) << "domain " << domain;
    }
  }
  b->primary(9, 0, got);
  sobol->primary(9, 0, want);
  EXPECT_NE(got, want);
}

// A version-1 plugin's roulette pair carries two 1D domains: roulette its
// x, the light choice its y; the lobe choice, which version 1 had no number
// for, is sobol's.
TEST(PluginBackend, AVersionOnePluginsPairsCarryTheOneDimensionalDomains) {
  auto b = makeBackend("plugin:" + kExample, 3);
  auto sobol = makeBackend("sobol", 3);
  b->prepare(16, image(8, 8));
  sobol->prepare(16, image(8, 8));
  EXPECT_NE(b->report().note.find("bounce 0's lobe-choice"), std::string::npos) << b->report().note;
  std::vector<double> roulette(16), choice(16), lobe(16), want(16);
  b->primary1D(5, SampleLayout::roulette(0), roulette);
  b->primary1D(5, SampleLayout::lightChoice(0), choice);
  EXPECT_NE(roulette, choice);
  b->primary1D(5, SampleLayout::lobeChoice(0), lobe);
  sobol->primary1D(5, SampleLayout::lobeChoice(0), want);
  EXPECT_EQ(lobe, want);
}

// The version-2 example is told the layout: it serves the roles its ARGS
// name, each dimension of a domain stratified into N (one number in each
// [k/N, (k+1)/N)), and leaves the rest to sobol.
TEST(PluginBackend, AVersionTwoPluginReadsTheRoles) {
  const std::string latin = NULD_EXAMPLE_LATIN_PLUGIN;
  auto b = makeBackend("plugin:" + latin + ":light,roulette", 3);
  auto sobol = makeBackend("sobol", 3);
  b->prepare(16, image(8, 8, 2));
  sobol->prepare(16, image(8, 8, 2));
  EXPECT_NE(b->report().note.find("serves 4 of the 11 domains"), std::string::npos)
      << b->report().note;
  const auto stratified = [](const std::vector<double> &v) {
    std::vector<int> seen(v.size(), 0);
    for (const double x : v) ++seen[std::size_t(x * double(v.size()))];
    return std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; });
  };
  std::vector<Point2> light(16), camera(16), want(16);
  b->primary(6, SampleLayout::light(1), light);
  std::vector<double> xs, ys;
  for (const Point2 &p : light) xs.push_back(p.x), ys.push_back(p.y);
  EXPECT_TRUE(stratified(xs) && stratified(ys));
  std::vector<double> roulette(16);
  b->primary1D(6, SampleLayout::roulette(0), roulette);
  EXPECT_TRUE(stratified(roulette));
  b->primary(6, SampleLayout::camera, camera);
  sobol->primary(6, SampleLayout::camera, want);
  EXPECT_EQ(camera, want);  // not a role it serves
  // A role it does not know is refused naming the word.
  auto typo = makeBackend("plugin:" + latin + ":lihgt", 3);
  const std::string message =
      test::errorMessage<BackendRefusal>([&] { typo->prepare(16, image(8, 8)); });
  EXPECT_NE(message.find("'lihgt' is not a role"), std::string::npos) << message;
}

}  // namespace
}  // namespace nuld
