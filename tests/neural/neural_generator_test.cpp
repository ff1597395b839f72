// The generator without training: the untrained net is its base set, wrapping
// into the domain, target families, save/load, and clear errors.

#include "sampler/neural/neural_generator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <utility>

#include "sampler/sequences/sobol.h"
#include "tests/common/temp_dir.h"
#include "tests/neural/expect_load_error.h"
#include "tests/neural/test_families.h"
#include "tests/neural/tiny_settings.h"

namespace nuld {
namespace {

NeuralSettings tiny(const std::string &family, std::size_t n = 37, int hidden = 16,
                    bool mapped = true) {
  return test::tinyNeuralSettings(family, n, hidden, mapped, 5);
}

TEST(NeuralGenerator, UntrainedSquareOutputIsTheRotatedSobolSetExactly) {
  // N = 37 (not a power of two) and a family with gamma.
  const NeuralGenerator gen(tiny("family:gaussian", 37, 16, false));
  const std::vector<Point2> z = {{0.3, 0.9}, {0.0, 0.0}, {0.999, 0.5}};
  const std::vector<double> gamma = {0.1, 0.2, 0.3, 0.5, 0.5, 0.5, 1, 0, 1};
  std::vector<Point2> out(3 * 37);
  gen.generate(z, gamma, out);
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t i = 0; i < 37; ++i) {
      double x = sobolSample(i, 0) + z[k].x, y = sobolSample(i, 1) + z[k].y;
      x -= std::floor(x);
      y -= std::floor(y);
      EXPECT_EQ(out[k * 37 + i].x, x);
      EXPECT_EQ(out[k * 37 + i].y, y);
    }
}

TEST(NeuralGenerator, UntrainedDirectionsAreTheUnwrappedBaseMappedIntoTheDomain) {
  test::registerTestSphereFamily();
  const NeuralGenerator gen(tiny("family:test-sphere", 1));  // N = 1
  EXPECT_EQ(gen.domain(), Domain::Sphere);
  const NeuralGenerator sphere(tiny("family:test-sphere", 64, 16, false));
  const Point2 z{0.75, 0.6};
  std::vector<Point2> base(64), out(64);
  sphere.baseSet(z, base);
  sphere.generate(std::vector<Point2>{z}, {}, out);
  bool crossed = false;
  for (std::size_t i = 0; i < 64; ++i) {
    // Not wrapped for directions (supplement §1)...
    EXPECT_EQ(base[i].x, sobolSample(i, 0) + z.x);
    EXPECT_EQ(base[i].y, sobolSample(i, 1) + z.y);
    crossed |= base[i].y > 1;
    // ...until the output is mapped onto the sphere.
    EXPECT_EQ(out[i], wrapToDomain(base[i], Domain::Sphere));
  }
  EXPECT_TRUE(crossed);
}

TEST(NeuralGenerator, UntrainedMappedOutputIsTheInverseCdfOfTheBaseSet) {
  const NeuralGenerator gen(tiny("family:gaussian", 37, 16, true));
  const std::vector<double> gamma = {0.2, 0.7, 0.4};
  const auto target = gen.family().target(gamma);
  const Point2 z{0.61, 0.05};
  std::vector<Point2> base(37), out(37);
  gen.baseSet(z, base);
  gen.generate(std::vector<Point2>{z}, gamma, out);
  for (std::size_t i = 0; i < 37; ++i) EXPECT_EQ(out[i], target->invert(base[i]).x);
}

TEST(TargetFamily, BuildsMembersAndRejectsBadGamma) {
  const auto gauss = makeTargetFamily("family:gaussian:0.1,0.2");
  EXPECT_EQ(gauss->gammaDimension(), 3u);
  const std::vector<double> g = {0.25, 0.75, 1.0};
  EXPECT_EQ(gauss->target(g)->spec(), makeTargetFamily(gauss->spec())->target(g)->spec());
  EXPECT_NE(gauss->target(g)->spec().find("0.2"), std::string::npos);
  EXPECT_THROW(gauss->target(std::vector<double>{0.5, 0.5}), std::invalid_argument);
  EXPECT_THROW(gauss->target(std::vector<double>{0.5, 0.5, 1.5}), std::invalid_argument);
  EXPECT_THROW(gauss->target(std::vector<double>{0.5, 0.5, std::nan("")}), std::invalid_argument);
  const auto bil = makeTargetFamily("family:bilinear");
  EXPECT_EQ(bil->gammaDimension(), 4u);
  EXPECT_NEAR(bil->target(std::vector<double>{0, 0, 0, 0})->mass({{0, 0}, {1, 1}}), 1, 1e-12);
  const auto fixed = makeTargetFamily("quarterdisc");
  EXPECT_EQ(fixed->gammaDimension(), 0u);
  EXPECT_EQ(fixed->target({})->spec(), "quarterdisc");
  EXPECT_THROW(makeTargetFamily("family:nosuch"), std::invalid_argument);
  EXPECT_THROW(makeTargetFamily("family:gaussian:0.3,0.1"), std::invalid_argument);
  EXPECT_THROW(makeTargetFamily("family:bilinear:1"), std::invalid_argument);
}

TEST(NeuralGenerator, SaveLoadRoundTripsAndRebuildsTheSameNet) {
  test::TempDir dir;
  const NeuralGenerator gen(tiny("family:gaussian", 16, 24));
  const std::string path = (dir / "g.nuldnet").string();
  gen.save(path);
  const NeuralGenerator back = NeuralGenerator::load(path);
  EXPECT_EQ(back.settings().n, 16u);
  EXPECT_EQ(back.settings().hidden, 24);
  EXPECT_EQ(back.settings().family, gen.settings().family);
  EXPECT_EQ(back.parameterCount(), gen.parameterCount());
  const std::vector<double> gamma = {0.5, 0.5, 0.5};
  const PointSet a = gen.generateSets(1, 9, gamma), b = back.generateSets(1, 9, gamma);
  EXPECT_EQ(a.points, b.points);
}

// The z harmonics: every integer frequency pair up to the order, one of each
// +- pair, with zero gamma columns, after the Gaussian rows; they survive a
// save and load, and a file that predates them loads without them.
TEST(NeuralGenerator, ZHarmonicsAreTheTorusFrequenciesAndRoundTrip) {
  test::TempDir dir;
  NeuralSettings s = tiny("family:gaussian", 16, 8);
  s.zHarmonics = 3;
  const NeuralGenerator gen(s);
  const ModelFile file = gen.toModelFile();
  const ModelTensor &B = file.tensor("B", "in memory");
  const std::int64_t gaussianRows = s.encodingDims / 2, cols = 2 + 3, harmonics = (7 * 7 - 1) / 2;
  ASSERT_EQ(B.shape, (std::vector<std::int64_t>{gaussianRows + harmonics, cols}));
  std::set<std::pair<int, int>> seen;
  for (std::int64_t r = gaussianRows; r < gaussianRows + harmonics; ++r) {
    const float a = B.data[r * cols], b = B.data[r * cols + 1];
    EXPECT_EQ(a, std::round(a));
    EXPECT_EQ(b, std::round(b));
    EXPECT_LE(std::max(std::abs(a), std::abs(b)), 3.0f);
    for (std::int64_t c = 2; c < cols; ++c) EXPECT_EQ(B.data[r * cols + c], 0.0f);
    EXPECT_TRUE(seen.insert({int(a), int(b)}).second) << a << ' ' << b;
    EXPECT_FALSE(seen.count({-int(a), -int(b)})) << "both of a +- pair";
  }
  EXPECT_FALSE(seen.count({0, 0}));

  const std::string path = (dir / "h.nuldnet").string();
  gen.save(path);
  const NeuralGenerator back = NeuralGenerator::load(path);
  EXPECT_EQ(back.settings().zHarmonics, 3);
  const std::vector<double> gamma = {0.5, 0.5, 0.5};
  EXPECT_EQ(gen.generateSets(2, 9, gamma).points, back.generateSets(2, 9, gamma).points);

  ModelFile old = NeuralGenerator(tiny("quarterdisc", 8, 8)).toModelFile();
  old.metadata.erase("z_harmonics");
  writeModelFile((dir / "old").string(), old);
  EXPECT_EQ(NeuralGenerator::load((dir / "old").string()).settings().zHarmonics, 0);
  NeuralSettings bad = tiny("quarterdisc", 8, 8);
  bad.zHarmonics = -1;
  EXPECT_THROW(NeuralGenerator{bad}, std::invalid_argument);
}

// The offset range scales the rotation (base(z) with range R is base(R z)
// with range 1), survives a save and load, and files that predate it load
// with the supplement's full range.
TEST(NeuralGenerator, OffsetRangeScalesTheRotationAndRoundTrips) {
  test::TempDir dir;
  NeuralSettings s = tiny("quarterdisc", 16, 8);
  s.offsetRange = 1.0 / 64;
  const NeuralGenerator narrow(s), full(tiny("quarterdisc", 16, 8));
  const Point2 z{0.7, 0.3};
  std::vector<Point2> a(16), b(16);
  narrow.baseSet(z, a);
  full.baseSet({z.x / 64, z.y / 64}, b);
  EXPECT_EQ(a, b);
  full.baseSet(z, b);
  EXPECT_NE(a, b);

  const std::string path = (dir / "r.nuldnet").string();
  narrow.save(path);
  const NeuralGenerator back = NeuralGenerator::load(path);
  EXPECT_EQ(back.settings().offsetRange, 1.0 / 64);
  EXPECT_EQ(narrow.generateSets(2, 5, {}).points, back.generateSets(2, 5, {}).points);

  ModelFile old = full.toModelFile();
  old.metadata.erase("offset_range");
  writeModelFile((dir / "old").string(), old);
  EXPECT_EQ(NeuralGenerator::load((dir / "old").string()).settings().offsetRange, 1.0);
  for (const double bad : {0.0, -0.5, 1.5}) {
    NeuralSettings t = tiny("quarterdisc", 8, 8);
    t.offsetRange = bad;
    EXPECT_THROW(NeuralGenerator{t}, std::invalid_argument) << bad;
  }
}

TEST(NeuralGenerator, ForeignOrInconsistentModelFilesAreClearErrors) {
  test::TempDir dir;
  using test::expectLoadError;
  ModelFile other;
  other.metadata["format"] = "something-else";
  writeModelFile((dir / "other").string(), other);
  expectLoadError((dir / "other").string(), "not a neural generator");

  NeuralGenerator gen(tiny("quarterdisc", 8, 8));
  ModelFile file = gen.toModelFile();
  file.metadata["hidden"] = "9";  // the weights no longer fit the described net
  writeModelFile((dir / "shape").string(), file);
  expectLoadError((dir / "shape").string(), "wrong shape");
  file = gen.toModelFile();
  file.metadata["n"] = "eight";
  writeModelFile((dir / "n").string(), file);
  expectLoadError((dir / "n").string(), "'n'");
  file = gen.toModelFile();
  file.metadata["family"] = "family:nosuch";
  writeModelFile((dir / "family").string(), file);
  expectLoadError((dir / "family").string(), "nosuch");
  file = gen.toModelFile();
  file.metadata.erase("sigma");
  writeModelFile((dir / "sigma").string(), file);
  expectLoadError((dir / "sigma").string(), "sigma");
}

// A generator whose network is built on first use (NetworkLoad::OnFirstUse,
// the renderer's) describes its model without one, makes the same sets as
// one loaded at once, and refuses weights that do not fit at its first
// generate(), naming the file; the network is then not half built.
TEST(NeuralGenerator, NetworkBuiltOnFirstUseMakesTheSameSets) {
  test::TempDir dir;
  const std::string path = (dir / "model").string();
  NeuralGenerator(tiny("quarterdisc", 8, 8)).save(path);
  const NeuralGenerator now = NeuralGenerator::load(path);
  const NeuralGenerator later =
      NeuralGenerator::load(path, NeuralGenerator::NetworkLoad::OnFirstUse);
  EXPECT_EQ(later.fileChecksum(), now.fileChecksum());
  EXPECT_EQ(later.settings().family, now.settings().family);
  EXPECT_EQ(later.generateSets(4, 9, {}).points, now.generateSets(4, 9, {}).points);

  ModelFile file = now.toModelFile();
  file.metadata["hidden"] = "9";  // the weights no longer fit the described net
  const std::string shape = (dir / "shape").string();
  writeModelFile(shape, file);
  const NeuralGenerator bad =
      NeuralGenerator::load(shape, NeuralGenerator::NetworkLoad::OnFirstUse);
  for (int attempt = 0; attempt < 2; ++attempt) {
    try {
      bad.generateSets(1, 1, {});
      FAIL() << "weights of the wrong shape were taken";
    } catch (const std::runtime_error &e) {
      EXPECT_NE(std::string(e.what()).find(shape), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("wrong shape"), std::string::npos) << e.what();
    }
  }
}

TEST(NeuralGenerator, RejectsBadSettingsAndGamma) {
  EXPECT_THROW(NeuralGenerator(tiny("uniform", 0)), std::invalid_argument);
  NeuralSettings s = tiny("uniform");
  s.encodingDims = 7;
  EXPECT_THROW(NeuralGenerator{s}, std::invalid_argument);
  const NeuralGenerator gen(tiny("family:gaussian", 4, 4));
  std::vector<Point2> out(4);
  EXPECT_THROW(gen.generate(std::vector<Point2>{{0.5, 0.5}}, std::vector<double>{0.5}, out),
               std::invalid_argument);
  EXPECT_THROW(gen.generate(std::vector<Point2>{{0.5, 0.5}}, std::vector<double>{0.5, 2, 0.5}, out),
               std::invalid_argument);
}

}  // namespace
}  // namespace nuld
