// The environment light against its own definition: radiance over pdf is the
// same constant everywhere (sampling is proportional to luminance), sampling
// follows pdf() (chi-square on the equal-area square, expected counts by
// integrating pdf() over each bin), and degenerate maps behave.

#include "renderer/environment_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "materials/sphere_map.h"
#include "sampler/sequences/rng.h"
#include "tests/common/chi_square.h"

namespace nuld {
namespace {

Image randomMap(int w, int h, std::uint64_t seed) {
  Image img{w, h, 3, std::vector<float>(std::size_t(w) * h * 3)};
  Rng rng(seed);
  for (float &v : img.pixels) v = float(std::pow(rng.uniform(), 4) * 10);
  return img;
}

// A map with black rows (the top quarter and one row in the middle) and one
// pixel 1e6 times brighter than the rest.
Image hardMap() {
  Image img = randomMap(32, 16, 7);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x)
      for (int c = 0; c < 3; ++c)
        if (y < 4 || y == 9) img.at(x, y, c) = 0;
  for (int c = 0; c < 3; ++c) img.at(20, 12, c) = 1e6f;
  return img;
}

std::string probePath() {
  return std::string(NULD_SOURCE_DIR) + "/../shared/assets/envmaps/grace_probulator_256x128.hdr";
}

void expectRadianceOverPdfConstant(const EnvironmentLight &light) {
  Rng rng(3);
  double ratio = -1;
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 w = sphereDirection({rng.uniform(), rng.uniform()});
    const double pdf = light.pdf(w), lum = light.radiance(w).luminance();
    if (pdf == 0) {
      EXPECT_EQ(lum, 0) << "radiance where the light never samples";
      continue;
    }
    if (ratio < 0) ratio = lum / pdf;
    EXPECT_NEAR(lum / pdf, ratio, 1e-6 * ratio);
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(EnvironmentLight, RadianceOverPdfIsConstantForAnyRotation) {
  for (double rotation : {0.0, 37.0, -120.0}) {
    const EnvironmentLight light(randomMap(64, 32, 1), 2.5, rotation, "random");
    expectRadianceOverPdfConstant(light);
    const EnvironmentLight hard(hardMap(), 1.0, rotation, "hard");
    expectRadianceOverPdfConstant(hard);
  }
}

// The pdf is constant over each map pixel; summing pdf x solid angle over the
// pixels (a closed form) must give 1, hot pixel and black rows included.
double pixelSolidAngle(int y, int W, int H) {
  const double t0 = std::numbers::pi * y / H, t1 = std::numbers::pi * (y + 1) / H;
  return 2 * std::numbers::pi / W * (std::cos(t0) - std::cos(t1));
}

double pixelPdf(const EnvironmentLight &light, int x, int y) {
  const int W = light.width(), H = light.height();
  const double theta = std::numbers::pi * (y + 0.5) / H;
  return light.pdf(light.toWorld(sphereDirection({(x + 0.5) / W, 0.5 * (1 - std::cos(theta))})));
}

TEST(EnvironmentLight, PdfIntegratesToOne) {
  for (double rotation : {0.0, 10.0}) {
    const EnvironmentLight light(hardMap(), 1.0, rotation, "hard");
    double sum = 0;
    for (int y = 0; y < light.height(); ++y)
      for (int x = 0; x < light.width(); ++x)
        sum += pixelPdf(light, x, y) * pixelSolidAngle(y, light.width(), light.height());
    EXPECT_NEAR(sum, 1.0, 1e-9);
  }
}

// Bins are the map's own pixels, whose pdf is constant: the expected count
// of pixel (x, y) is n * pdf * its solid angle (2 pi / W)(cos theta0 - cos theta1),
// a closed form independent of the sampling code.
void chiSquareLight(const EnvironmentLight &light, const char *what) {
  const int W = light.width(), H = light.height();
  std::vector<double> observed(std::size_t(W) * H, 0.0);
  const auto pixelOf = [&](Vec3 world) {
    const Point2 p = spherePoint(light.toLocal(world));
    const int x = std::min(W - 1, int(p.x * W));
    const int y = std::min(H - 1, int(std::acos(1 - 2 * p.y) / std::numbers::pi * H));
    return std::size_t(y) * W + x;
  };
  Rng rng(11);
  const int n = 400000;
  for (int i = 0; i < n; ++i) {
    const auto s = light.sample({rng.uniform(), rng.uniform()});
    ASSERT_TRUE(s.has_value());
    ASSERT_NEAR(s->pdf, light.pdf(s->wi), 1e-9 * s->pdf);
    observed[pixelOf(s->wi)] += 1;
  }
  std::vector<double> expected(std::size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      expected[std::size_t(y) * W + x] = n * pixelPdf(light, x, y) * pixelSolidAngle(y, W, H);
  const test::ChiSquare r = test::pooledChiSquare(observed, expected);
  EXPECT_GT(r.pValue, test::sidakLevel(0.01, 3)) << what << " " << r.note;
}

TEST(EnvironmentLight, SamplingFollowsPdfChiSquare) {
  chiSquareLight(EnvironmentLight(randomMap(64, 32, 2), 1.0, 25.0, "random"), "random map");
  chiSquareLight(EnvironmentLight(hardMap(), 1.0, 0.0, "hard"), "zero rows and a hot pixel");
  if (!std::filesystem::exists(probePath())) GTEST_SKIP() << "no probe at " << probePath();
  chiSquareLight(EnvironmentLight(readImage(probePath()), 1.0, 0.0, probePath()), "grace probe");
}

// Weighted by the channels' mean (pbrt-v4's and Cycles' choice), a red and a
// blue pixel of one row are equally likely; by luminance, the red one is
// 0.2126 / 0.0722 times more. The pdf still integrates to one, sampling
// follows it, and the target says which weighting it is.
TEST(EnvironmentLight, ChannelMeanWeightsPixelsByTheirChannelMean) {
  Image map{4, 2, 3, std::vector<float>(4 * 2 * 3, 0.0f)};
  map.at(0, 0, 0) = 1;  // red
  map.at(2, 0, 2) = 1;  // blue, the same row
  map.at(1, 1, 1) = 0.5;
  const EnvironmentLight mean(map, 1.0, 0.0, "rgb", {0, 1, 0}, PixelWeight::ChannelMean);
  const EnvironmentLight luminance(map, 1.0, 0.0, "rgb");
  EXPECT_NEAR(pixelPdf(mean, 0, 0) / pixelPdf(mean, 2, 0), 1.0, 1e-12);
  EXPECT_NEAR(pixelPdf(luminance, 0, 0) / pixelPdf(luminance, 2, 0), 0.2126 / 0.0722, 1e-9);
  EXPECT_EQ(mean.target()->spec(), "envmap-mean:rgb");
  EXPECT_EQ(luminance.target()->spec(), "envmap:rgb");
  const EnvironmentLight random(randomMap(64, 32, 2), 1.0, 25.0, "random", {0, 1, 0},
                                PixelWeight::ChannelMean);
  double sum = 0;
  for (int y = 0; y < random.height(); ++y)
    for (int x = 0; x < random.width(); ++x)
      sum += pixelPdf(random, x, y) * pixelSolidAngle(y, random.width(), random.height());
  EXPECT_NEAR(sum, 1.0, 1e-9);
  chiSquareLight(random, "random map, channel mean");
}

// MIS compensation: the density is the weight less its mean over the sphere,
// clamped at 0 and normalized; sampling follows it; a constant map, which
// nothing exceeds, keeps its plain density.
TEST(EnvironmentLight, CompensatedDensityIsTheWeightAboveItsMean) {
  const Image map = randomMap(64, 32, 4);
  const EnvironmentLight plain(map, 1.0, 0.0, "random", {0, 1, 0}, PixelWeight::ChannelMean);
  const EnvironmentLight compensated(map, 1.0, 0.0, "random", {0, 1, 0},
                                     PixelWeight::ChannelMeanCompensated);
  EXPECT_EQ(compensated.target()->spec(), "envmap-mean-compensated:random");
  // The mean over the sphere, from the plain weights and the solid angles.
  double mean = 0, sum = 0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const double w = (double(map.at(x, y, 0)) + map.at(x, y, 1) + map.at(x, y, 2)) / 3.0;
      mean += w * pixelSolidAngle(y, map.width, map.height) / (4 * std::numbers::pi);
    }
  const double offset = envmapCompensation(map, PixelWeight::ChannelMeanCompensated);
  EXPECT_NEAR(offset, mean, 1e-8 * mean);
  mean = offset;  // the same to rounding; the pdf subtracts exactly this
  int zero = 0;
  double ratio = -1;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const double w = (double(map.at(x, y, 0)) + map.at(x, y, 1) + map.at(x, y, 2)) / 3.0;
      const double pdf = pixelPdf(compensated, x, y);
      sum += pdf * pixelSolidAngle(y, map.width, map.height);
      if (w <= mean) {
        EXPECT_EQ(pdf, 0) << x << "," << y;
        ++zero;
        continue;
      }
      if (ratio < 0) ratio = pdf / (w - mean);
      EXPECT_NEAR(pdf / (w - mean), ratio, 1e-6 * ratio);
    }
  EXPECT_NEAR(sum, 1.0, 1e-9);
  EXPECT_GT(zero, 0);
  chiSquareLight(compensated, "random map, compensated");
  // A constant map: no pixel above the mean, so the plain density.
  Image flat{8, 4, 3, std::vector<float>(96, 2.0f)};
  EXPECT_EQ(envmapCompensation(flat, PixelWeight::LuminanceCompensated), 0.0);
  const EnvironmentLight flatLight(flat, 1.0, 0.0, "flat", {0, 1, 0},
                                   PixelWeight::LuminanceCompensated);
  EXPECT_NEAR(flatLight.pdf({0, 1, 0}), 1 / (4 * std::numbers::pi), 1e-12);
  EXPECT_GT(plain.pdf(sphereDirection({0.3, 0.4})), 0);
}

TEST(EnvironmentLight, SamplesNeverComeFromBlackRows) {
  const EnvironmentLight light(hardMap(), 1.0, 0.0, "hard");
  Rng rng(5);
  for (int i = 0; i < 100000; ++i) {
    const auto s = light.sample({rng.uniform(), rng.uniform()});
    ASSERT_TRUE(s);
    EXPECT_GT(s->radiance.luminance(), 0);
    EXPECT_TRUE(std::isfinite(s->pdf) && s->pdf > 0);
  }
}

TEST(EnvironmentLight, BlackMapHasNoSamplesAndZeroPdf) {
  const EnvironmentLight light(Image{8, 4, 3, std::vector<float>(96, 0.0f)}, 1.0, 0.0, "black");
  EXPECT_EQ(light.target(), nullptr);
  EXPECT_FALSE(light.sample({0.3, 0.7}));
  EXPECT_EQ(light.pdf({0, 1, 0}), 0);
  EXPECT_TRUE(light.radiance({0, 1, 0}).isBlack());
}

TEST(EnvironmentLight, MapOrientation) {
  // Row 0 is the zenith (+Y); column u = 0 faces -Z and u = 1/4 faces +X.
  Image img{4, 2, 3, std::vector<float>(24, 0.0f)};
  img.at(0, 0, 0) = 1;  // top row, first column: red
  img.at(1, 1, 1) = 1;  // bottom row, second column: green
  const EnvironmentLight light(img, 1.0, 0.0, "tiny");
  EXPECT_GT(light.radiance(normalize(Vec3{0.1, 1, -1})).r, 0);
  EXPECT_GT(light.radiance(normalize(Vec3{1, -1, 0.3})).g, 0);
  // Rotating the map by 90 degrees about +Y turns -Z into -X.
  const EnvironmentLight turned(img, 1.0, 90.0, "tiny");
  EXPECT_GT(turned.radiance(normalize(Vec3{-1, 1, -0.1})).r, 0);
  // up = -Y sets an upside-down map right: the top row now lights from below
  // (the half-turn about +X, which also takes -Z to +Z).
  const EnvironmentLight flipped(img, 1.0, 0.0, "tiny", {0, -1, 0});
  EXPECT_GT(flipped.radiance(normalize(Vec3{0.1, -1, 1})).r, 0);
  EXPECT_GT(flipped.radiance(normalize(Vec3{1, 1, -0.3})).g, 0);
}

// Any up direction (with any rotation) turns the map rigidly: the frame is
// orthonormal with its z on `up` and the default frame's handedness (x x y =
// -z: seen from above, u runs clockwise from -Z to +X), toLocal inverts toWorld,
// and radiance and pdf are the unturned map's at the turned-back direction.
TEST(EnvironmentLight, UpDirectionTurnsTheMapRigidly) {
  const Image map = randomMap(64, 32, 4);
  const EnvironmentLight plain(map, 1.0, 0.0, "random");
  Rng rng(5);
  for (const Vec3 up : {Vec3{0, -1, 0}, Vec3{1, 1, 0}, Vec3{0.2, -0.3, 0.9}, Vec3{0, 1, 1e-9}})
    for (const double rotation : {0.0, 75.0}) {
      const EnvironmentLight light(map, 1.0, rotation, "random", up);
      const Vec3 x = light.toWorld({1, 0, 0}), y = light.toWorld({0, 1, 0}),
                 z = light.toWorld({0, 0, 1});
      EXPECT_NEAR(length(z - normalize(up)), 0, 1e-12);
      EXPECT_NEAR(dot(x, y), 0, 1e-12);
      EXPECT_NEAR(length(cross(x, y) + z), 0, 1e-12);
      for (int i = 0; i < 200; ++i) {
        const Vec3 w = sphereDirection({rng.uniform(), rng.uniform()});
        const Vec3 local = light.toLocal(w);
        EXPECT_NEAR(length(light.toWorld(local) - w), 0, 1e-12);
        // The plain map's frame at rotation 0 is the reference: the same
        // map-frame direction must see the same texel.
        const Vec3 back = plain.toWorld(local);
        EXPECT_EQ(light.pdf(w), plain.pdf(back));
        EXPECT_EQ(light.radiance(w).r, plain.radiance(back).r);
      }
    }
  EXPECT_THROW(EnvironmentLight(map, 1.0, 0.0, "zero", {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(EnvironmentLight(map, 1.0, 0.0, "nan", {0, std::nan(""), 1}), std::invalid_argument);
}

TEST(EnvironmentLight, RejectsBadInput) {
  Image nan = randomMap(8, 4, 1);
  nan.at(3, 2, 1) = std::nanf("");
  EXPECT_THROW(EnvironmentLight(nan, 1.0, 0.0, "nan"), std::invalid_argument);
  EXPECT_THROW(EnvironmentLight(randomMap(8, 4, 1), -1.0, 0.0, "neg"), std::invalid_argument);
}

// The batch forms (which overlap their memory reads) give exactly what one
// call per point gives, over more points than one group and on a map with
// black rows, including the edges of the square.
TEST(EnvironmentLight, BatchSamplingEqualsOneAtATime) {
  for (const Image &map : {randomMap(64, 32, 5), hardMap()}) {
    const EnvironmentLight light(map, 1.5, 30.0, "batch");
    Rng rng(11);
    std::vector<Point2> u(37);
    for (Point2 &p : u) p = {rng.uniform(), rng.uniform()};
    u[0] = {0, 0};
    u[1] = {std::nextafter(1.0, 0.0), std::nextafter(1.0, 0.0)};
    u[2] = {1, 1};
    u[3] = {0.5, 0.25};
    std::vector<std::optional<LightSample>> batch(u.size()), batchTarget(u.size());
    light.sample(u, batch);
    light.sampleTarget(u, batchTarget);
    for (std::size_t k = 0; k < u.size(); ++k) {
      const auto one = light.sample(u[k]), oneTarget = light.sampleTarget(u[k]);
      ASSERT_EQ(one.has_value(), batch[k].has_value()) << k;
      ASSERT_EQ(oneTarget.has_value(), batchTarget[k].has_value()) << k;
      if (one) {
        EXPECT_EQ(one->wi, batch[k]->wi) << k;
        EXPECT_EQ(one->radiance, batch[k]->radiance) << k;
        EXPECT_EQ(one->pdf, batch[k]->pdf) << k;
      }
      if (oneTarget) {
        EXPECT_EQ(oneTarget->wi, batchTarget[k]->wi) << k;
        EXPECT_EQ(oneTarget->radiance, batchTarget[k]->radiance) << k;
        EXPECT_EQ(oneTarget->pdf, batchTarget[k]->pdf) << k;
      }
    }
  }
}

}  // namespace
}  // namespace nuld
