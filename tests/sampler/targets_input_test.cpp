// Tests of the sampling targets' robustness and of the environment-map
// target (sampler/targets): finite inverse maps at the edges of the unit
// square, bad densities, specs and image files rejected with messages that
// name them, high dynamic range, and the env map's luminance-weighted
// solid-angle parameterization.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <system_error>
#include <type_traits>
#include <vector>

#include "sampler/diagnostics.h"
#include "sampler/io/image_io.h"
#include "sampler/point.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/grid_target.h"
#include "sampler/targets/image_targets.h"
#include "sampler/targets/target.h"
#include "sampler/targets/target_spec.h"
#include "tests/sampler/target_oracles.h"

namespace nuld {
namespace {

using test::allCases;
using test::Case;
using test::chiSquare;
using test::envmapImage;
using test::kPi;
using test::pictureImage;
using test::uniformEdges;
using ChiSquare = test::MassChiSquare;

// ------------------------------------------------------------ 4. stability, input

// Scale-free targets: weights or densities scaled by 1e-300 or 1e300 give
// the same density, masses and inverse as the ordinary ones (to 1e-12); a
// largest value below the normal doubles, or a Gaussian narrower than
// 1e-12, is refused naming the value.
TEST(TargetInput, ScaleFreeTargetsKeepTheirShapeAndRefuseUnderflow) {
  const std::array<double, 4> w{1, 2, 0.5, 3};
  const auto bilinear = [&](double k) {
    return std::make_unique<BilinearTarget>(w[0] * k, w[1] * k, w[2] * k, w[3] * k);
  };
  const std::vector<double> density{1, 4, 0, 2, 8, 1};
  const auto grid = [&](double k) {
    std::vector<double> d = density;
    for (double &v : d) v *= k;
    return std::make_unique<GridTarget>(uniformEdges(3), uniformEdges(2), d, "grid", Domain::Square,
                                        "test grid");
  };
  const auto same = [](const Target &a, const Target &b) {
    for (const Point2 u : {Point2{0.1, 0.2}, Point2{0.5, 0.9}, Point2{0.97, 0.03}}) {
      const Point2 xa = a.invert(u).x, xb = b.invert(u).x;
      EXPECT_NEAR(xa.x, xb.x, 1e-12);
      EXPECT_NEAR(xa.y, xb.y, 1e-12);
      EXPECT_NEAR(a.pdf(u), b.pdf(u), 1e-12 * b.pdf(u));
      EXPECT_NEAR(a.mass({{0, 0}, u}), b.mass({{0, 0}, u}), 1e-12);
    }
  };
  for (const double k : {1e-300, 1e-200, 1e200, 1e300}) {
    SCOPED_TRACE(k);
    same(*bilinear(k), *bilinear(1));
    same(*grid(k), *grid(1));
  }
  const auto refusal = [](const auto &make) {
    try {
      make();
    } catch (const std::invalid_argument &e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal([] { makeTarget("bilinear:1e-320,1e-320,0,1e-321"); }).find("1e-320"),
            std::string::npos);
  EXPECT_NE(refusal([&] { grid(1e-320); }).find("underflows"), std::string::npos);
  EXPECT_NE(refusal([] { makeTarget("gaussian:0.5,0.5,1e-300"); }).find("sigma 1e-300"),
            std::string::npos);
  EXPECT_NO_THROW(makeTarget("gaussian:0.5,0.5,1e-12"));
}

TEST(TargetInput, InvertIsFiniteAtTheEdges) {
  const double below1 = std::nextafter(1.0, 0.0);
  const std::vector<Point2> us = {{0, 0},
                                  {1, 1},
                                  {0, 1},
                                  {1, 0},
                                  {0.999999999999, 0},
                                  {0, 0.999999999999},
                                  {below1, below1},
                                  {0.5, 0},
                                  {0.5, 1},
                                  {0, 0.5},
                                  {1, 0.5},
                                  {1e-300, 1e-300},
                                  {std::numeric_limits<double>::denorm_min(), 0.5},
                                  {1e-16, 1 - 1e-16}};
  std::vector<std::shared_ptr<const Target>> targets;
  for (const Case &c : allCases()) targets.push_back(c.target);
  for (const char *s :
       {"bilinear:0,1,0,1", "bilinear:0,0,0,1", "bilinear:1,0,0,0", "step:0,1,2", "step:1,1,0",
        "step:0.999,0,1", "gaussian:0.5,0.5,0.001", "gaussian:-1,0.5,0.2", "gaussian:1.5,-0.5,0.1"})
    targets.push_back(makeTarget(s));
  for (const auto &t : targets)
    for (const Point2 u : us) {
      const Inversion inv = t->invert(u);
      const std::string where =
          t->spec() + " at u = (" + std::to_string(u.x) + ", " + std::to_string(u.y) + ")";
      EXPECT_TRUE(isFinite(inv.x)) << where;
      EXPECT_TRUE(inv.x.x >= 0 && inv.x.x <= 1 && inv.x.y >= 0 && inv.x.y <= 1)
          << where << ": x = (" << inv.x.x << ", " << inv.x.y << ")";
      for (int r = 0; r < 2; ++r)
        for (int col = 0; col < 2; ++col)
          EXPECT_TRUE(std::isfinite(inv.jacobian.m[r][col]))
              << where << ": J[" << r << "][" << col << "] = " << inv.jacobian.m[r][col];
    }
}

// The message of the exception of type E that f throws, or a note saying
// what happened instead.
template <typename E, typename F>
std::string messageOf(F &&f) {
  try {
    f();
  } catch (const std::exception &e) {
    if constexpr (!std::is_same_v<E, std::exception>)
      if (!dynamic_cast<const E *>(&e))
        return std::string("<wrong exception type: ") + e.what() + ">";
    return e.what();
  }
  return "<no exception>";
}

bool contains(const std::string &s, const std::string &part) {
  return s.find(part) != std::string::npos;
}

TEST(TargetInput, GridRejectsBadDensities) {
  const auto e = uniformEdges(2);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::vector<double>> bad = {
      {0, 0, 0, 0}, {1, nan, 1, 1}, {1, 1, -0.5, 1}, {inf, 1, 1, 1}, {nan, nan, nan, nan}};
  for (const auto &d : bad) {
    const std::string msg = messageOf<std::invalid_argument>(
        [&] { GridTarget(e, e, d, "grid", Domain::Square, "densities-from-test.bin"); });
    EXPECT_TRUE(contains(msg, "densities-from-test.bin")) << msg;
  }
  // Wrong counts and bad edges are rejected too.
  EXPECT_THROW(GridTarget(e, e, {1, 1, 1}, "grid", Domain::Square, "src"), std::invalid_argument);
  EXPECT_THROW(GridTarget({0, 0.5, 0.5, 1}, e, {1, 1, 1, 1, 1, 1}, "grid", Domain::Square, "src"),
               std::invalid_argument);
  EXPECT_THROW(GridTarget({0, 0.5, 0.9}, e, {1, 1, 1, 1}, "grid", Domain::Square, "src"),
               std::invalid_argument);
  // An all-black image names its source.
  Image black = pictureImage();
  std::fill(black.pixels.begin(), black.pixels.end(), 0.0f);
  const std::string msg =
      messageOf<std::invalid_argument>([&] { makeImageTarget(black, "black-picture"); });
  EXPECT_TRUE(contains(msg, "black-picture")) << msg;
}

TEST(TargetInput, MakeTargetRejectsBadSpecs) {
  for (const char *spec : {"nosuchfamily",
                           "nosuchfamily:1,2",
                           "bilinear:1,2",
                           "bilinear:1,2,3,4,5",
                           "bilinear:",
                           "bilinear",
                           "gaussian:a,b,c",
                           "gaussian:0.5,0.5",
                           "gaussian:0.5,0.5,0",
                           "gaussian:0.5,0.5,-0.1",
                           "gaussian:0.5,0.5,nan",
                           "gaussian:0.5,0.5,1e400",
                           "gaussian:0.5,,0.1",
                           "bilinear:1,2,3,4,",
                           "bilinear:1,2,-3,4",
                           "bilinear:0,0,0,0",
                           "step:",
                           "step:1.5",
                           "step:0.5,1,2,3",
                           "step:1",
                           "step:0.5,-1,1",
                           "uniform:1",
                           "quarterdisc:2",
                           "image:",
                           "envmap:"}) {
    const std::string msg = messageOf<std::invalid_argument>([&] { makeTarget(spec); });
    EXPECT_TRUE(contains(msg, std::string("'") + spec + "'")) << spec << " -> " << msg;
  }
}

TEST(TargetInput, SpecsRoundTrip) {
  for (const char *spec : {"uniform", "quarterdisc", "bilinear:1,2,0.5,3", "gaussian:0.3,0.6,0.15",
                           "step:0.4,1,3", "step:0.5"}) {
    const auto t = makeTarget(spec);
    const auto again = makeTarget(t->spec());
    EXPECT_EQ(again->spec(), t->spec()) << spec;
    const Box2 box{{0.1, 0.2}, {0.55, 0.9}};
    EXPECT_EQ(again->mass(box), t->mass(box)) << spec;
  }
}

struct TempDir {
  std::filesystem::path path;
  TempDir() {
    path = std::filesystem::temp_directory_path() /
           ("nuld_targets_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string file(const std::string &name) const { return (path / name).string(); }
};

Image constantImage(int w, int h, float v) {
  Image img;
  img.width = w;
  img.height = h;
  img.channels = 1;
  img.pixels.assign(std::size_t(w) * h, v);
  return img;
}

TEST(TargetInput, ImageFileErrorsNameTheFile) {
  const std::string missing = "/nonexistent-nuld-dir/nonexistent.png";
  for (const std::string family : {"image:", "envmap:"}) {
    const std::string msg = messageOf<std::exception>([&] { makeTarget(family + missing); });
    EXPECT_TRUE(contains(msg, missing)) << msg;
  }

  TempDir dir;
  Image img = constantImage(4, 4, 1.0f);
  img.at(2, 1, 0) = std::numeric_limits<float>::quiet_NaN();
  const std::string nanPath = dir.file("nan-pixel.exr");
  writeImage(nanPath, img);
  for (const std::string family : {"image:", "envmap:"}) {
    const std::string msg = messageOf<std::exception>([&] { makeTarget(family + nanPath); });
    EXPECT_TRUE(contains(msg, nanPath)) << msg;
  }

  const std::string blackPath = dir.file("black.exr");
  writeImage(blackPath, constantImage(4, 4, 0.0f));
  const std::string msg = messageOf<std::exception>([&] { makeTarget("image:" + blackPath); });
  EXPECT_TRUE(contains(msg, blackPath)) << msg;
}

// A header that claims more pixels than the machine can hold is refused
// with the numbers before anything is allocated (a PFM header costs a few
// bytes to write; the file holds almost nothing behind it).
TEST(TargetInput, ImageHeaderBeyondMemoryIsRefusedBeforeAllocating) {
  TempDir dir;
  const std::string path = dir.file("huge.pfm");
  std::ofstream(path, std::ios::binary) << "PF\n1000000 1000000\n-1.0\n" << std::string(64, '\0');
  const std::string msg = messageOf<std::exception>([&] { readImage(path); });
  EXPECT_TRUE(contains(msg, path)) << msg;
  EXPECT_TRUE(contains(msg, "1000000 x 1000000 image of 3 channels needs about 10.9 TiB")) << msg;
  EXPECT_TRUE(contains(msg, "more than this machine's")) << msg;
}

// Negative pixels carry no probability: the density there is 0, and the
// user is told how many there were (sampler/diagnostics.h).
TEST(TargetInput, NegativePixelsBecomeZeroDensityWithAWarning) {
  std::vector<std::string> warnings;
  const WarningHandler previous =
      setWarningHandler([&](const std::string &m) { warnings.push_back(m); });
  TempDir dir;
  Image img{4, 2, 3, std::vector<float>(24, 1.0f)};
  for (int c = 0; c < 3; ++c) img.at(1, 0, c) = -0.5f;
  img.at(3, 1, 0) = -9.0f;  // a negative luminance from one channel
  const std::string path = dir.file("negative.exr");
  writeImage(path, img);
  const auto image = makeTarget("image:" + path);
  const auto envmap = makeTarget("envmap:" + path);
  setWarningHandler(previous);
  ASSERT_EQ(warnings.size(), 2u);
  for (const std::string &w : warnings) {
    EXPECT_TRUE(contains(w, path)) << w;
    EXPECT_TRUE(contains(w, "2 of 8 pixels have a negative weight (down to -1.13)")) << w;
  }
  // Image rows run top-down, the square's y bottom-up: pixel (1, 0) is the
  // cell [0.25, 0.5] x [0.5, 1].
  EXPECT_NEAR(image->mass({{0.25, 0.5}, {0.5, 1}}), 0.0, 1e-15);
  EXPECT_GT(image->mass({{0, 0.5}, {0.25, 1}}), 0.0);
  warnings.clear();
  makeTarget("image:" + dir.file("negative.exr"));  // the handler is the default again
  EXPECT_TRUE(warnings.empty());
}

// Two specs name the same target when equal, or when an image or a map is
// the same file reached through another path; never across families (an
// envmap: and an envmap-mean: target of one file differ in density).
TEST(TargetInput, SameTargetComparesFilesNotSpellings) {
  TempDir dir;
  writeImage(dir.file("sky.exr"), constantImage(4, 2, 1.0f));
  const std::string direct = dir.file("sky.exr");
  const std::string roundabout = (dir.path / "." / "sky.exr").string();
  EXPECT_TRUE(sameTarget("quarterdisc", "quarterdisc"));
  EXPECT_FALSE(sameTarget("quarterdisc", "uniform"));
  for (const std::string family : {"image:", "envmap:", "envmap-mean:"})
    EXPECT_TRUE(sameTarget(family + direct, family + roundabout)) << family;
  EXPECT_FALSE(sameTarget("envmap:" + direct, "envmap-mean:" + roundabout));
  EXPECT_FALSE(sameTarget("envmap:" + direct, "envmap:" + dir.file("other.exr")));
  EXPECT_EQ(makeTarget("envmap-mean:" + direct)->spec(), "envmap-mean:" + direct);
}

TEST(TargetInput, HighDynamicRangeImage) {
  // One pixel at 1e6, the other 15 at 1: the hot pixel holds 1e6 / (1e6 + 15).
  TempDir dir;
  Image img = constantImage(4, 4, 1.0f);
  const int hotX = 1, hotY = 0;  // image row 0 is the top of the picture (y = 1)
  img.at(hotX, hotY, 0) = 1e6f;
  const std::string path = dir.file("hot.exr");
  writeImage(path, img);
  const auto fromFile = makeTarget("image:" + path);
  const auto fromMemory = makeImageTarget(img, "hot");
  const double expected = 1e6 / (1e6 + 15);
  const Box2 hotCell{{0.25 * hotX, 0.75 - 0.25 * hotY}, {0.25 * (hotX + 1), 1.0 - 0.25 * hotY}};
  for (const Target *t : std::vector<const Target *>{fromFile.get(), fromMemory.get()}) {
    EXPECT_NEAR(t->mass(hotCell), expected, 1e-12 * expected) << t->spec();
    const Box2 coldCell{{0.5, 0.25}, {0.75, 0.5}};
    EXPECT_NEAR(t->mass(coldCell), 1 / (1e6 + 15), 1e-9 / (1e6 + 15)) << t->spec();
  }
  // Points that land in the hot cell: binomial, 5 standard deviations.
  const int n = 4000000;
  Rng rng(42);
  int hot = 0;
  for (int k = 0; k < n; ++k) {
    const Point2 x = fromFile->invert({rng.uniform(), rng.uniform()}).x;
    if (hotCell.contains(x)) ++hot;
  }
  const double mean = n * expected, sd = std::sqrt(n * expected * (1 - expected));
  EXPECT_NEAR(hot, mean, 5 * sd) << "expected " << n - mean << " points outside the hot cell";
  const ChiSquare r = chiSquare(*fromFile, *fromFile, 1000000, 4, 43);
  EXPECT_GT(r.pValue, 0.01) << "chi^2 = " << r.statistic << ", dof " << r.dof;
}

// ------------------------------------------------------------------ 5. envmap

// Rec. 709 luminance, written out independently of Image::luminance.
double luminance709(const Image &img, int i, int j) {
  if (img.channels < 3) return img.at(i, j, 0);
  return 0.2126 * img.at(i, j, 0) + 0.7152 * img.at(i, j, 1) + 0.0722 * img.at(i, j, 2);
}

TEST(TargetEnvmap, BandMassIsLuminanceWeightedSolidAngle) {
  const Image img = envmapImage();
  const int W = img.width, H = img.height;
  const auto target = makeEnvmapTarget(img, "memory-envmap");
  EXPECT_EQ(target->domain(), Domain::Sphere);
  // Independent reference: sum of L * solid angle over the lat-long pixels,
  // row j covering theta in [pi j / H, pi (j + 1) / H], theta = 0 the zenith.
  std::vector<double> weight(std::size_t(W) * H);
  double total = 0;
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) {
      const double solidAngle =
          (2 * kPi / W) * (std::cos(kPi * j / H) - std::cos(kPi * (j + 1) / H));
      weight[std::size_t(j) * W + i] = std::max(0.0, luminance709(img, i, j)) * solidAngle;
      total += weight[std::size_t(j) * W + i];
    }
  auto reference = [&](int i0, int i1, int j0, int j1) {
    double s = 0;
    for (int j = j0; j < j1; ++j)
      for (int i = i0; i < i1; ++i) s += weight[std::size_t(j) * W + i];
    return s / total;
  };
  auto v = [&](int j) { return 0.5 * (1 - std::cos(kPi * j / H)); };
  for (int j0 = 0; j0 < H; ++j0)
    for (int j1 = j0 + 1; j1 <= H; ++j1) {
      const Box2 band{{0, v(j0)}, {1, v(j1)}};
      EXPECT_NEAR(target->mass(band), reference(0, W, j0, j1), 1e-12)
          << "rows " << j0 << " to " << j1;
    }
  // The upper hemisphere is v in [0, 1/2].
  EXPECT_NEAR(target->mass({{0, 0}, {1, 0.5}}), reference(0, W, 0, H / 2), 1e-12);
  // Partial longitude ranges.
  const std::vector<std::array<int, 4>> blocks = {
      {0, 1, 0, 1}, {3, 7, 1, 4}, {2, 6, 4, 5}, {5, 8, 2, 6}};
  for (auto [i0, i1, j0, j1] : blocks) {
    const Box2 b{{double(i0) / W, v(j0)}, {double(i1) / W, v(j1)}};
    EXPECT_NEAR(target->mass(b), reference(i0, i1, j0, j1), 1e-12)
        << "columns " << i0 << "-" << i1 << ", rows " << j0 << "-" << j1;
  }
  // The same map read from a float EXR file.
  TempDir dir;
  const std::string path = dir.file("envmap.exr");
  writeImage(path, img);
  const auto fromFile = makeTarget("envmap:" + path);
  EXPECT_EQ(fromFile->domain(), Domain::Sphere);
  for (int j0 = 0; j0 < H; ++j0)
    EXPECT_NEAR(fromFile->mass({{0.1, v(j0)}, {0.8, v(H)}}),
                target->mass({{0.1, v(j0)}, {0.8, v(H)}}), 1e-15);
  // The density per unit (u, v) area is luminance per solid angle, row 0 at v
  // near 0: pdf = L / (sum L dOmega) * 4 pi.
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) {
      const Point2 center{(i + 0.5) / W, 0.5 * (v(j) + v(j + 1))};
      const double expected = std::max(0.0, luminance709(img, i, j)) / total * 4 * kPi;
      EXPECT_NEAR(target->pdf(center), expected, 1e-12 * std::max(1.0, expected))
          << "pixel " << i << ", " << j;
    }
}

}  // namespace
}  // namespace nuld
