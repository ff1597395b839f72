// Sampler backends: the classic ones are what they claim (Owen-scrambled
// Sobol points of a pixel form a (0, m, 2)-net), and the point-set backend
// serves its file's points where it should, falls back where it should, and
// refuses a render it cannot serve with a message that says why.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <tuple>

#include "backends/backend_registry.h"
#include "backends/bank_backend.h"
#include "renderer/environment_light.h"
#include "renderer/image_metrics.h"
#include "renderer/padding.h"
#include "renderer/render.h"
#include "sampler/io/pointset_io.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/target_spec.h"
#include "tests/common/chi_square.h"
#include "tests/common/temp_dir.h"
#include "tests/renderer/test_scenes.h"

namespace nuld {
namespace {

namespace fs = std::filesystem;

// Every elementary box of area 1/N (N = 2^m) holds exactly one point.
bool isNet(const std::vector<Point2> &pts) {
  const int m = int(std::log2(pts.size()));
  for (int a = 0; a <= m; ++a) {
    const int nx = 1 << a, ny = 1 << (m - a);
    std::vector<int> count(std::size_t(nx) * ny, 0);
    for (const Point2 &p : pts) ++count[std::size_t(int(p.y * ny)) * nx + int(p.x * nx)];
    for (int c : count)
      if (c != 1) return false;
  }
  return true;
}

// The t of a (t, m, 2)-net of N = 2^m points: the smallest t for which every
// elementary box of area 2^(t - m) holds 2^t points.
int netQuality(const std::vector<Point2> &pts) {
  const int m = int(std::log2(pts.size()));
  for (int t = 0; t <= m; ++t) {
    bool all = true;
    for (int a = 0; a <= m - t && all; ++a) {
      const int nx = 1 << a, ny = 1 << (m - t - a);
      std::vector<int> count(std::size_t(nx) * ny, 0);
      for (const Point2 &p : pts) ++count[std::size_t(int(p.y * ny)) * nx + int(p.x * nx)];
      all = std::all_of(count.begin(), count.end(), [&](int c) { return c == 1 << t; });
    }
    if (all) return t;
  }
  return m;
}

// sobol-full: a pixel's domains are consecutive dimensions of one sequence,
// so numbers of different domains are stratified together (the camera's x
// with the light choice, Sobol dimensions 0 and 2, are a (1, 6, 2)-net of 64
// points), where sobol's padded domains are matched at random; every domain
// is still stratified.
TEST(Backends, SobolFullDomainsAreOneSequencesDimensions) {
  SamplingTargets targets;
  targets.width = 8, targets.height = 8, targets.domains = SampleLayout::domains(5);
  const auto full = makeBackend("sobol-full", 5), padded = makeBackend("sobol", 5);
  full->prepare(64, targets);
  padded->prepare(64, targets);
  EXPECT_NE(full->report().note.find("bounce 3 on are padded"), std::string::npos)
      << full->report().note;
  const auto across = [](SamplerBackend &b, std::uint64_t pixel) {
    std::vector<Point2> camera(64);
    std::vector<double> choice(64);
    b.primary(pixel, SampleLayout::camera, camera);
    b.primary1D(pixel, SampleLayout::lightChoice(0), choice);
    std::vector<Point2> joint(64);
    for (std::size_t i = 0; i < 64; ++i) joint[i] = {camera[i].x, choice[i]};
    return joint;
  };
  for (std::uint64_t pixel : {0ull, 9ull, 63ull}) {
    EXPECT_LE(netQuality(across(*full, pixel)), 1) << pixel;
    EXPECT_GE(netQuality(across(*padded, pixel)), 3) << pixel;
    std::vector<Point2> camera(64), light(64);
    full->primary(pixel, SampleLayout::camera, camera);
    EXPECT_TRUE(isNet(camera));
    std::vector<Point2> other(64);
    full->primary(pixel + 1, SampleLayout::camera, other);
    EXPECT_NE(camera, other);  // every pixel scrambled afresh
  }
  // A domain past Sobol's dimensions is a padded set, still a net.
  std::vector<Point2> deep(64);
  full->primary(3, SampleLayout::bsdf(4), deep);
  EXPECT_TRUE(isNet(deep));
}

TEST(Backends, SobolPixelsAreNetsAndPairsAreIndependentlyScrambled) {
  const auto sobol = makeBackend("sobol", 5);
  std::vector<Point2> a(64), b(64), c(64);
  sobol->primary(17, SampleLayout::light(0), a);
  sobol->primary(17, SampleLayout::bsdf(0), b);
  sobol->primary(18, SampleLayout::light(0), c);
  EXPECT_TRUE(isNet(a) && isNet(b) && isNet(c));
  EXPECT_NE(a, b);
  EXPECT_NE(a, c);
  std::vector<Point2> again(64);
  sobol->primary(17, SampleLayout::light(0), again);
  EXPECT_EQ(a, again);
  // Independent points are (almost surely) not a net.
  const auto independent = makeBackend("independent", 5);
  independent->primary(17, SampleLayout::light(0), a);
  EXPECT_FALSE(isNet(a));
}

// Sample i of a pixel combines point i of every pair. The pairs of a pixel
// are scrambled copies of one net; matched by index, their points would be
// tied together (the first digits of two pairs' x equal or opposite for every
// i). Shuffled, (camera x, light x) and (light y, bsdf y) over the N samples
// must look like independent uniform pairs: chi-square on an 8 x 8 grid.
TEST(Backends, PairsOfAPixelAreMatchedAtRandom) {
  constexpr std::size_t N = 4096;
  constexpr int G = 8;
  for (const char *name : {"sobol", "halton"}) {
    const auto backend = makeBackend(name, 3);
    for (std::uint64_t pixel : {0u, 17u, 40000u}) {
      std::vector<Point2> camera(N), light(N), bsdf(N);
      backend->primary(pixel, SampleLayout::camera, camera);
      backend->primary(pixel, SampleLayout::light(0), light);
      backend->primary(pixel, SampleLayout::bsdf(0), bsdf);
      if (std::string(name) == "sobol") {
        EXPECT_TRUE(isNet(light)) << "shuffling keeps the net";
      }
      // The same coordinate of two pairs: scrambled copies of one dimension.
      for (const auto &[a, b, useX] :
           {std::tuple{&camera, &light, true}, std::tuple{&light, &bsdf, false}}) {
        std::vector<double> observed(G * G, 0), expected(G * G, double(N) / (G * G));
        for (std::size_t i = 0; i < N; ++i) {
          const Point2 pa = (*a)[i], pb = (*b)[i];
          ++observed[int((useX ? pa.x : pa.y) * G) * G + int((useX ? pb.x : pb.y) * G)];
        }
        // Both margins are stratified (exactly N / G per row and column), so
        // the statistic is that of a contingency table: (G - 1)^2 dof.
        const double stat = test::pooledChiSquare(observed, expected).statistic;
        const double p = test::regularizedGammaQ(0.5 * (G - 1) * (G - 1), 0.5 * stat);
        EXPECT_GT(p, test::sidakLevel(0.01, 12)) << name << " pixel " << pixel;
      }
    }
  }
}

// shufflePoints draws every permutation equally often: all 24 of 4 points
// and all 120 of 5 (odd and even sizes take the two-swaps-per-draw loop's
// both exits), chi-square over 120000 seeds; sizes 0 and 1 are left alone.
TEST(Padding, ShuffleDrawsEveryPermutationEquallyOften) {
  for (int n : {4, 5}) {
    std::map<std::vector<int>, double> counts;
    const int seeds = 120000;
    for (int seed = 0; seed < seeds; ++seed) {
      std::vector<Point2> pts(n);
      for (int i = 0; i < n; ++i) pts[i] = {double(i), 0};
      shufflePoints(pts, std::uint64_t(seed));
      std::vector<int> order(n);
      for (int i = 0; i < n; ++i) order[i] = int(pts[i].x);
      ++counts[order];
    }
    const std::size_t perms = n == 4 ? 24 : 120;
    ASSERT_EQ(counts.size(), perms);
    std::vector<double> observed, expected;
    for (const auto &[order, c] : counts)
      observed.push_back(c), expected.push_back(double(seeds) / perms);
    EXPECT_GT(test::pooledChiSquare(observed, expected).pValue, 1e-4) << "n " << n;
  }
  std::vector<Point2> none, one = {{0.5, 0.5}};
  shufflePoints(none, 1);
  shufflePoints(one, 1);
  EXPECT_EQ(one[0], (Point2{0.5, 0.5}));
}

TEST(Backends, UnknownNameListsTheChoices) {
  try {
    makeBackend("sobolo", 0);
    FAIL();
  } catch (const std::invalid_argument &e) {
    const std::string what = e.what();
    for (const BackendEntry &e : backendRegistry())
      EXPECT_NE(what.find(e.spelling()), std::string::npos) << e.spelling() << " in " << what;
    EXPECT_NE(what.find("nuld help backends"), std::string::npos) << what;
  }
  EXPECT_THROW(makeBackend("optimized:/no/such/file.txt", 0), std::exception);
}

TEST(BankBackend, UniformSetsAreShiftedPerPixelAndDeeperPairsFallBack) {
  PointSet set;
  set.n = 8;
  Rng rng(1);
  for (int i = 0; i < 3 * 8; ++i) set.points.push_back({rng.uniform(), rng.uniform()});
  set.metadata["target"] = "uniform";
  BankBackend backend("optimized:test", {{set, "test"}}, 4);
  backend.prepare(8, {});
  std::vector<Point2> out(8);
  backend.primary(11, SampleLayout::bsdf(0), out);
  // out is one of the instances under a toroidal shift, in some order (the
  // pairs' points are shuffled, see renderer/padding.h).
  const auto same = [](Point2 a, Point2 b) {
    return std::abs(std::remainder(a.x - b.x, 1.0)) < 1e-12 &&
           std::abs(std::remainder(a.y - b.y, 1.0)) < 1e-12;
  };
  bool found = false;
  for (std::size_t k = 0; k < 3 && !found; ++k) {
    const auto inst = set.instance(k);
    for (int j = 0; j < 8 && !found; ++j) {  // out[0] is inst[j] shifted
      const Point2 shift{out[0].x - inst[j].x, out[0].y - inst[j].y};
      bool all = true;
      for (int i = 0; i < 8 && all; ++i) {
        bool matched = false;
        for (int m = 0; m < 8 && !matched; ++m)
          matched = same(out[i], {inst[m].x + shift.x, inst[m].y + shift.y});
        all = matched;
      }
      found = all;
    }
  }
  EXPECT_TRUE(found);
  // A deeper pair falls back to Owen-scrambled Sobol with the same seed.
  std::vector<Point2> deep(8), sobol(8);
  backend.primary(11, SampleLayout::light(1), deep);
  makeBackend("sobol", 4)->primary(11, SampleLayout::light(1), sobol);
  EXPECT_EQ(deep, sobol);
  EXPECT_THROW(backend.prepare(16, {}), std::invalid_argument);
}

TEST(BankBackend, DistributedSetsServeOnlyTheirTargetAtTheFirstBounce) {
  const test::TempDir dir;
  const std::string mapPath = (dir / "map.exr").string();
  test::writeHotPixelMap(mapPath);
  const EnvironmentLight light(readImage(mapPath), 1.0, 0.0, mapPath);
  const EnvironmentLight other(test::constantMap(1.0f), 1.0, 0.0, "other.exr");

  PointSet set;
  set.n = 4;
  for (int i = 0; i < 2 * 4; ++i) set.points.push_back({0.1 * i, 0.05 * i});
  // The same file reached through a different spelling of its path.
  set.metadata["target"] = "envmap:" + (dir.path() / "." / "map.exr").string();
  BankBackend backend("optimized:x", {{set, "x.ptsb"}}, 0);
  EXPECT_NO_THROW(backend.prepare(4, {light.target()}));
  std::vector<Point2> out(4);
  ASSERT_TRUE(backend.distributed(*light.target(), 5, SampleLayout::light(0), out));
  // One of the instances, in some order (shuffled like every pair).
  const auto sorted = [](auto points) {
    std::vector<Point2> v(points.begin(), points.end());
    std::sort(v.begin(), v.end(), [](Point2 a, Point2 b) { return a.x < b.x; });
    return v;
  };
  EXPECT_TRUE(sorted(out) == sorted(set.instance(0)) || sorted(out) == sorted(set.instance(1)));
  EXPECT_FALSE(backend.distributed(*light.target(), 5, SampleLayout::light(1), out));

  const auto message = [&](std::size_t spp, const Target *t) {
    try {
      backend.prepare(spp, {t});
    } catch (const std::invalid_argument &e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(8, light.target()).find("--spp 4"), std::string::npos);
  EXPECT_NE(message(4, nullptr).find("no environment map"), std::string::npos);
  EXPECT_NE(message(4, other.target()).find("other.exr"), std::string::npos);
}

// A nested bank (metadata `prefixes`) serves any spp up to its N by the
// first spp points of an instance; the same map copied under another path
// is matched by its content hash; a plain bank of another N is refused.
TEST(BankBackend, NestedBanksServePrefixesAndMapsMatchByContent) {
  const test::TempDir dir;
  const std::string mapPath = (dir / "map.exr").string(), copyPath = (dir / "copy.exr").string();
  test::writeHotPixelMap(mapPath);
  fs::copy_file(mapPath, copyPath);
  const EnvironmentLight light(readImage(mapPath), 1.0, 0.0, mapPath);
  const EnvironmentLight copy(readImage(copyPath), 1.0, 0.0, copyPath);

  PointSet set;
  set.n = 8;
  for (int i = 0; i < 2 * 8; ++i) set.points.push_back({0.05 * i + 0.01, 0.03 * i + 0.02});
  recordTarget(set, *light.target());
  setMeta(set, meta::kPrefixes, "2,4,8");
  BankBackend nested("optimized:n", {{set, "n.ptsb"}}, 0);
  for (std::size_t spp : {2, 4, 5, 8}) {
    ASSERT_NO_THROW(nested.prepare(spp, {copy.target()})) << spp;
    std::vector<Point2> out(spp);
    ASSERT_TRUE(nested.distributed(*copy.target(), 9, SampleLayout::light(0), out)) << spp;
    std::vector<Point2> sorted(out), first0, first1;
    const auto byX = [](Point2 a, Point2 b) { return a.x < b.x; };
    std::sort(sorted.begin(), sorted.end(), byX);
    for (std::size_t i = 0; i < spp; ++i) {
      first0.push_back(set.instance(0)[i]);
      first1.push_back(set.instance(1)[i]);
    }
    std::sort(first0.begin(), first0.end(), byX);
    std::sort(first1.begin(), first1.end(), byX);
    EXPECT_TRUE(sorted == first0 || sorted == first1) << "the first " << spp << " points";
  }
  EXPECT_THROW(nested.prepare(16, {light.target()}), std::invalid_argument);

  set.metadata.erase(std::string(meta::kPrefixes));
  BankBackend plain("optimized:p", {{set, "p.ptsb"}}, 0);
  EXPECT_NO_THROW(plain.prepare(8, {copy.target()}));
  EXPECT_THROW(plain.prepare(4, {copy.target()}), std::invalid_argument);
}

// A file of inverse-CDF-mapped Owen-Sobol sets, served as distributed points,
// renders the same image in expectation as the sobol backend: both estimate
// the same integral, so both land close to a converged reference.
TEST(BankBackend, DistributedPointsRenderTheSameImage) {
  Image sky = test::constantMap(0.2f, 32, 16);
  for (int c = 0; c < 3; ++c) sky.at(10, 4, c) = 80.0f;
  const test::TempDir dir;
  const std::string mapPath = (dir / "sky.exr").string();
  writeImage(mapPath, sky);
  Scene scene =
      test::sceneWith({test::unitSphere()}, {std::make_shared<Lambertian>(Rgb::grey(0.8))},
                      std::nullopt, {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40, false});
  scene.environment.emplace(readImage(mapPath), 1.0, 0.0, mapPath);

  const std::size_t spp = 16;
  PointSet set;
  set.n = spp;
  for (std::uint32_t k = 0; k < 32; ++k) {
    std::vector<Point2> u(spp);
    makeBackend("sobol", 77)->primary(k, 0, u);
    for (const Point2 &p : u) set.points.push_back(scene.environment->target()->invert(p).x);
  }
  set.metadata["target"] = scene.environment->target()->spec();
  BankBackend optimized("optimized:mapped", {{set, "mapped"}}, 3);

  const RenderSettings settings{16, 16, spp, IntegratorKind::Direct, 1};
  auto ref = makeBackend("sobol", 99);
  const Image reference = render(scene, {16, 16, 4096, IntegratorKind::Direct, 1}, *ref);
  auto sobol = makeBackend("sobol", 3);
  const double mseSobol = compareImages(render(scene, settings, *sobol), reference).mse;
  const double mseFile = compareImages(render(scene, settings, optimized), reference).mse;
  EXPECT_LT(mseFile, 3 * mseSobol);
  EXPECT_LT(mseSobol, 3 * mseFile);
}

}  // namespace
}  // namespace nuld

namespace nuld {
namespace {

// Every word the registry declares, its aliases included, parses to its
// kind and prints back canonically; arguments are required exactly where
// declared, and the help's spellings are the registry's.
TEST(BackendRegistry, EveryWordParsesToItsKindAndBack) {
  std::vector<BackendKind> kinds;
  for (const BackendEntry &e : backendRegistry()) {
    kinds.push_back(e.kind);
    const std::string argument = e.argument.empty() ? "" : "some/file";
    for (const std::string &word : [&] {
           std::vector<std::string> w{e.name};
           w.insert(w.end(), e.aliases.begin(), e.aliases.end());
           return w;
         }()) {
      const std::string text = argument.empty() ? word : word + ":" + argument;
      const BackendSpec spec = parseBackend(text);
      EXPECT_EQ(spec.kind, e.kind) << text;
      EXPECT_EQ(spec.argument, argument) << text;
      EXPECT_EQ(spec.text(), argument.empty() ? e.name : e.name + ":" + argument) << text;
      EXPECT_EQ(parseBackend(spec.text()), spec);
      // An argument where none is declared, or none where one is required
      // (an optional one left out parses to the empty argument).
      if (argument.empty() || !e.optionalArgument) {
        EXPECT_THROW(parseBackend(argument.empty() ? word + ":x" : word), std::invalid_argument)
            << word;
      } else {
        EXPECT_EQ(parseBackend(word), (BackendSpec{e.kind, ""})) << word;
        EXPECT_EQ(parseBackend(word).text(), e.name) << word;
      }
    }
    EXPECT_NE(backendSpellings().find(e.spelling()), std::string::npos) << e.spelling();
    EXPECT_FALSE(e.help.empty()) << e.name;
    EXPECT_EQ(&backendEntry(e.kind), &e);
  }
  EXPECT_EQ(kinds.size(), 23u);
  // The classic words make their backends without files, named by their
  // word; the declared properties agree with what the backends report.
  for (const char *word : {"independent", "random", "sobol", "halton", "sobol-tabulated",
                           "independent-tabulated", "halton-tabulated", "stratified", "jittered",
                           "pmj02", "zsobol", "lattice", "lattice-baker"}) {
    const BackendSpec spec = parseBackend(word);
    const auto backend = makeBackend(spec, 1);
    EXPECT_EQ(backend->samplesLobes(), spec.entry().lobes) << word;
    EXPECT_EQ(backend->name(), spec.entry().name) << word;
  }
  EXPECT_EQ(makeBackend("random", 3)->name(), "independent");
}

// Each entry declares where it serves, what a command makes first and
// whether +shift applies; the parser and the factory hold to them.
TEST(BackendRegistry, UsesSetsAndShiftAreTheEntries) {
  for (const BackendEntry &e : backendRegistry()) {
    const std::string word = e.argument.empty() || e.optionalArgument ? e.name : e.name + ":f";
    for (const unsigned use : {unsigned(kRenders), unsigned(kIntegration)}) {
      if (e.uses & use)
        EXPECT_NO_THROW(parseBackend(word, use)) << word;
      else
        EXPECT_THROW(parseBackend(word, use), std::invalid_argument) << word;
      EXPECT_EQ(backendSpellings(use).find(e.spelling()) != std::string::npos, (e.uses & use) != 0)
          << e.name;
    }
    if (e.shiftable) {
      const BackendSpec shifted = parseBackend(word + "+shift");
      EXPECT_TRUE(shifted.shift) << word;
      EXPECT_EQ(parseBackend(shifted.text()), shifted) << word;
    } else {
      EXPECT_THROW(parseBackend(word + "+shift"), std::invalid_argument) << word;
    }
    const BackendSpec spec = parseBackend(word);
    EXPECT_EQ(spec.setsToMake(), spec.argument.empty() ? e.makes : BackendSets::None) << word;
    // What makes its sets first, or serves the integration study only, is
    // refused by the factory with the reason.
    if (spec.setsToMake() != BackendSets::None || !e.serves(kRenders))
      EXPECT_THROW(makeBackend(spec, 1), std::invalid_argument) << word;
  }
  // A file's sets with +shift are the shifted backend.
  EXPECT_EQ(parseBackend("optimized:a.txt+shift"), (BackendSpec{BackendKind::Shifted, "a.txt"}));
  EXPECT_EQ(parseBackend("optimized").setsToMake(), BackendSets::EnvMap);
  EXPECT_EQ(parseBackend("optimized-both").setsToMake(), BackendSets::EnvMapAndLobes);
}

}  // namespace
}  // namespace nuld
