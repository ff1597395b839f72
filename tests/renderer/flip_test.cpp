#include "renderer/flip.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace nuld {
namespace {

using flip::Color;

void setPixel(Image &img, int x, int y, float r, float g, float b) {
  img.at(x, y, 0) = r;
  img.at(x, y, 1) = g;
  img.at(x, y, 2) = b;
}

Image filled(int w, int h, float r, float g, float b) {
  Image img{w, h, 3, std::vector<float>(std::size_t(w) * h * 3)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) setPixel(img, x, y, r, g, b);
  return img;
}

// Deterministic noise in [0, scale) (a 64-bit LCG: no dependence on the
// standard library's distributions).
Image noise(int w, int h, std::uint64_t seed, float scale = 1.0f, int channels = 3) {
  Image img{w, h, channels, std::vector<float>(std::size_t(w) * h * channels)};
  for (float &v : img.pixels) {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    v = scale * float(seed >> 40) / float(1 << 24);
  }
  return img;
}

void expectColorNear(const Color &a, const Color &b, double tol) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol) << "component " << c;
}

std::string thrownMessage(const auto &call) {
  try {
    call();
  } catch (const std::invalid_argument &e) {
    return e.what();
  }
  return "(nothing thrown)";
}

TEST(Flip, PixelsPerDegreeAtTheDefaults) {
  // 0.7 m x (3840 px / 0.7 m) x pi / 180, FLIP's small-angle form.
  EXPECT_NEAR(FlipViewing{}.pixelsPerDegree(), 67.0206, 1e-4);
  EXPECT_DOUBLE_EQ(FlipViewing{}.pixelsPerDegree(), 3840 * std::numbers::pi / 180);
  EXPECT_DOUBLE_EQ((FlipViewing{1.4, 0.7, 3840}.pixelsPerDegree()),
                   2 * FlipViewing{}.pixelsPerDegree());
  // Non-positive viewing values are errors naming the value.
  const auto message = [](const FlipViewing &v) {
    return thrownMessage([&] { v.pixelsPerDegree(); });
  };
  EXPECT_NE(message({0, 0.7, 3840}).find("monitorDistanceMeters"), std::string::npos);
  EXPECT_NE(message({0.7, -1, 3840}).find("monitorWidthMeters"), std::string::npos);
  const Image a = filled(8, 8, 0.5f, 0.5f, 0.5f);
  EXPECT_THROW(ldrFlip(a, a, FlipViewing{0.7, 0.7, std::nan("")}), std::invalid_argument);
  EXPECT_THROW(hdrFlip(a, a, FlipViewing{0.7, 0.7, 0}), std::invalid_argument);
}

TEST(Flip, ColorTransformsOfWhiteBlackAndPrimariesByHand) {
  // The sRGB -> XYZ matrix's columns are the primaries' XYZ; its row sums
  // are the reference white.
  const Color white = {23359437.0 / 24577794, 12288897.0 / 12288897, 80288307.0 / 73733382};
  expectColorNear(flip::referenceWhite(), white, 1e-15);
  expectColorNear(flip::xyzToYcxcz(flip::linearRgbToXyz({1, 1, 1})), {100, 0, 0}, 1e-12);
  expectColorNear(flip::xyzToYcxcz(flip::linearRgbToXyz({0, 0, 0})), {-16, 0, 0}, 1e-12);
  expectColorNear(flip::xyzToLab(flip::linearRgbToXyz({1, 1, 1})), {100, 0, 0}, 1e-12);
  expectColorNear(flip::xyzToLab(flip::linearRgbToXyz({0, 0, 0})), {0, 0, 0}, 1e-12);
  const Color primaries[3] = {{10135552.0 / 24577794, 2613072.0 / 12288897, 1425312.0 / 73733382},
                              {8788810.0 / 24577794, 8788810.0 / 12288897, 8788810.0 / 73733382},
                              {4435075.0 / 24577794, 887015.0 / 12288897, 70074185.0 / 73733382}};
  for (int p = 0; p < 3; ++p) {
    Color rgb = {0, 0, 0};
    rgb[p] = 1;
    const Color &xyz = primaries[p];
    expectColorNear(flip::linearRgbToXyz(rgb), xyz, 1e-15);
    const double x = xyz[0] / white[0], y = xyz[1], z = xyz[2] / white[2];
    const Color ycxcz = {116 * y - 16, 500 * (x - y), 200 * (y - z)};
    expectColorNear(flip::xyzToYcxcz(xyz), ycxcz, 1e-12);
    // And back: the inverse matrix undoes the forward one.
    expectColorNear(flip::xyzToLinearRgb(flip::ycxczToXyz(ycxcz)), rgb, 1e-12);
  }
  // Blue's L* (Y = 0.0722 > (6/29)^3 takes the cube root).
  EXPECT_NEAR(flip::xyzToLab(primaries[2])[0], 116 * std::cbrt(primaries[2][1]) - 16, 1e-12);
  // The sRGB curve (IEC 61966-2-1).
  EXPECT_DOUBLE_EQ(flip::srgbToLinear(0.04), 0.04 / 12.92);  // the linear toe
  EXPECT_NEAR(flip::srgbToLinear(0.5), std::pow(0.555 / 1.055, 2.4), 1e-15);
  EXPECT_NEAR(flip::srgbToLinear(1), 1, 1e-15);
  for (const double v : {0.0, 0.01, 0.2, 0.5, 0.9, 1.0})
    EXPECT_NEAR(flip::linearToSrgb(flip::srgbToLinear(v)), v, 1e-12);
}

TEST(Flip, HuntHyabAndCmax) {
  // Hunt scales the chroma by L* / 100; HyAB is |dL| + the Euclidean
  // distance in (a, b): 10 + |(3, 4)| = 15.
  expectColorNear(flip::huntAdjust({50, 20, -40}), {50, 10, -20}, 1e-12);
  EXPECT_DOUBLE_EQ(flip::hyab({50, 10, 20}, {40, 13, 24}), 15);
  EXPECT_DOUBLE_EQ(flip::hyab({40, 13, 24}, {50, 10, 20}), 15);
  EXPECT_DOUBLE_EQ(flip::hyab({30, 1, 2}, {30, 1, 2}), 0);
  const auto hunt = [](const Color &rgb) {
    return flip::huntAdjust(flip::xyzToLab(flip::linearRgbToXyz(rgb)));
  };
  const double cmax = flip::maxColorDifference();
  EXPECT_DOUBLE_EQ(cmax, std::pow(flip::hyab(hunt({0, 1, 0}), hunt({0, 0, 1})), 0.7));
  EXPECT_NEAR(cmax, 41.2761, 1e-4);
  // The paper's claim that makes cmax the normaliser: green-blue is the
  // largest Hunt-adjusted HyAB distance in the RGB cube (11^3 grid).
  std::vector<Color> labs;
  for (int r = 0; r <= 10; ++r)
    for (int g = 0; g <= 10; ++g)
      for (int b = 0; b <= 10; ++b) labs.push_back(hunt({r / 10.0, g / 10.0, b / 10.0}));
  double largest = 0;
  for (std::size_t i = 0; i < labs.size(); ++i)
    for (std::size_t j = i + 1; j < labs.size(); ++j)
      largest = std::max(largest, flip::hyab(labs[i], labs[j]));
  EXPECT_LE(std::pow(largest, 0.7), cmax * (1 + 1e-12));
}

TEST(Flip, CompressionAtItsBreakpoints) {
  const double cmax = flip::maxColorDifference(), knee = 0.4 * cmax;
  EXPECT_DOUBLE_EQ(flip::compressColorDifference(0), 0);
  EXPECT_NEAR(flip::compressColorDifference(knee), 0.95, 1e-12);
  EXPECT_NEAR(flip::compressColorDifference(knee * (1 - 1e-12)), 0.95, 1e-9);  // continuous
  EXPECT_NEAR(flip::compressColorDifference(knee / 2), 0.475, 1e-12);
  EXPECT_NEAR(flip::compressColorDifference(0.7 * cmax), 0.975, 1e-12);
  EXPECT_NEAR(flip::compressColorDifference(cmax), 1, 1e-12);
}

TEST(Flip, CsfKernelsHaveThePapersRadiusShapeAndUnitMass) {
  const double ppd = FlipViewing{}.pixelsPerDegree(), pi = std::numbers::pi;
  // ceil(3 sqrt(0.04 / (2 pi^2)) 67.02) = ceil(9.05).
  for (const auto channel :
       {flip::CsfChannel::Achromatic, flip::CsfChannel::RedGreen, flip::CsfChannel::BlueYellow}) {
    const flip::SeparableKernel k = flip::csfKernel(channel, ppd);
    EXPECT_EQ(k.radius, 10);
    double mass = 0;
    for (const auto &f : k.factors)
      for (const double a : f)
        for (const double b : f) mass += a * b;
    EXPECT_NEAR(mass, 1, 1e-12);
  }
  // The blue-yellow kernel's separable terms add up to the paper's 2D sum
  // of Gaussians: compare the ratio of a tap at (3, 4) to the centre.
  const flip::SeparableKernel by = flip::csfKernel(flip::CsfChannel::BlueYellow, ppd);
  ASSERT_EQ(by.factors.size(), 2u);
  const auto tap = [&](int i, int j) {
    double v = 0;
    for (const auto &f : by.factors) v += f[i + 10] * f[j + 10];
    return v;
  };
  const double r2 = 25 / (ppd * ppd);
  const auto g = [&](double a, double b, double z) {
    return a * std::sqrt(pi / b) * std::exp(-pi * pi * z / b);
  };
  EXPECT_NEAR(tap(3, 4) / tap(0, 0),
              (g(34.1, 0.04, r2) + g(13.5, 0.025, r2)) / (g(34.1, 0.04, 0) + g(13.5, 0.025, 0)),
              1e-12);
  EXPECT_EQ(flip::csfKernel(flip::CsfChannel::Achromatic, 2 * ppd).radius, 19);  // ceil(18.1)
}

TEST(Flip, FeatureKernelsAreNormalisedGaussianDerivatives) {
  const flip::FeatureKernels k = flip::featureKernels(FlipViewing{}.pixelsPerDegree());
  EXPECT_EQ(k.radius, 9);  // ceil(3 x 0.5 x 0.082 x 67.02) = ceil(8.24)
  double gauss = 0, edgePos = 0, edgeNeg = 0, pointPos = 0, pointNeg = 0;
  for (int i = 0; i < 2 * k.radius + 1; ++i) {
    gauss += k.gaussian[i];
    (k.edge[i] > 0 ? edgePos : edgeNeg) += k.edge[i];
    (k.point[i] > 0 ? pointPos : pointNeg) += k.point[i];
    EXPECT_DOUBLE_EQ(k.edge[i], -k.edge[2 * k.radius - i]);   // odd
    EXPECT_DOUBLE_EQ(k.point[i], k.point[2 * k.radius - i]);  // even
  }
  EXPECT_NEAR(gauss, 1, 1e-12);
  EXPECT_NEAR(edgePos, 1, 1e-12);
  EXPECT_NEAR(edgeNeg, -1, 1e-12);
  EXPECT_NEAR(pointPos, 1, 1e-12);
  EXPECT_NEAR(pointNeg, -1, 1e-12);
  EXPECT_LT(k.point[k.radius], 0);  // the second derivative's trough at the centre
  EXPECT_GT(k.edge[k.radius - 1], 0);
}

TEST(Flip, IdenticalImagesGiveExactlyZero) {
  const Image a = noise(40, 30, 1);
  const FlipResult r = ldrFlip(a, a);
  for (const float v : r.map) ASSERT_EQ(v, 0.0f);
  EXPECT_EQ(r.mean, 0);
  Image hdr = noise(40, 30, 2, 10);
  hdr.at(5, 5, 1) = 1e6f;
  const FlipResult h = hdrFlip(hdr, hdr);
  for (const float v : h.map) ASSERT_EQ(v, 0.0f);
  EXPECT_EQ(h.mean, 0);
}

TEST(Flip, BlackAgainstWhiteGivesTheHandValueInTheInterior) {
  // White's Hunt-adjusted Lab is (100, 0, 0), black's (0, 0, 0): HyAB 100,
  // past the knee, so 0.95 + (100^0.7 - 0.4 cmax) / (0.6 cmax) x 0.05.
  const double cmax = flip::maxColorDifference();
  const double expected = 0.95 + (std::pow(100.0, 0.7) - 0.4 * cmax) / (0.6 * cmax) * 0.05;
  EXPECT_NEAR(expected, 0.96738, 1e-5);
  // A white square on black: at its centre, 20 px from any edge (the CSF
  // and feature kernels reach 10 and 9 px), nothing of the edge shows.
  Image test = filled(80, 80, 0, 0, 0);
  for (int y = 20; y < 60; ++y)
    for (int x = 20; x < 60; ++x) setPixel(test, x, y, 1, 1, 1);
  const FlipResult r = ldrFlip(test, filled(80, 80, 0, 0, 0));
  EXPECT_NEAR(r.map[40 * 80 + 40], expected, 1e-5);
  EXPECT_NEAR(r.map[5 * 80 + 5], 0, 1e-6);  // black on black, far from the square
  // Green against blue is cmax itself: the largest error, 1.
  const FlipResult gb = ldrFlip(filled(16, 16, 0, 1, 0), filled(16, 16, 0, 0, 1));
  for (const float v : gb.map) EXPECT_NEAR(v, 1, 1e-5);
}

TEST(Flip, SymmetricInItsImagesAndUnderMirroring) {
  const Image a = noise(37, 23, 3), b = noise(37, 23, 4);
  const FlipResult ab = ldrFlip(a, b), ba = ldrFlip(b, a);
  EXPECT_EQ(ab.map, ba.map);  // HyAB and the feature difference are symmetric
  // The kernels are even or odd and the borders clamp alike on both sides,
  // so mirroring both images mirrors the map (up to summation order).
  const auto mirror = [](const Image &img) {
    Image m = img;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        for (int c = 0; c < 3; ++c) m.at(x, y, c) = img.at(img.width - 1 - x, y, c);
    return m;
  };
  const FlipResult mm = ldrFlip(mirror(a), mirror(b));
  for (int y = 0; y < 23; ++y)
    for (int x = 0; x < 37; ++x) ASSERT_NEAR(mm.map[y * 37 + x], ab.map[y * 37 + 36 - x], 1e-5);
}

TEST(Flip, ShiftedEdgeHasMoreFeatureErrorThanAnEqualMseBrightnessChange) {
  // Linear images: an edge from 0.2 to 0.8 at x = 32; moved one pixel
  // (one column off by 0.6: MSE 0.36 / 64) or everything raised by 0.075
  // (MSE 0.075^2 = 0.36 / 64).
  const auto edge = [](int at, float lift) {
    Image img = filled(64, 64, 0, 0, 0);
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const float v = (x < at ? 0.2f : 0.8f) + lift;
        setPixel(img, x, y, v, v, v);
      }
    return img;
  };
  const double ppd = FlipViewing{}.pixelsPerDegree();
  const flip::Stages shifted = flip::ldrFlipLinear(edge(33, 0), edge(32, 0), ppd);
  const flip::Stages lifted = flip::ldrFlipLinear(edge(32, 0.075f), edge(32, 0), ppd);
  const float shiftedMax = *std::max_element(shifted.feature.begin(), shifted.feature.end());
  const float liftedMax = *std::max_element(lifted.feature.begin(), lifted.feature.end());
  EXPECT_GT(shiftedMax, 0.3f);
  EXPECT_GT(shiftedMax, 10 * liftedMax);
  // The FLIP value follows: where the edge moved, the error outgrows the
  // colour error alone (colour^(1 - feature) >= colour).
  const std::size_t at = 32 * 64 + 32;
  EXPECT_GT(shifted.flip[at], shifted.color[at]);
}

TEST(Flip, ClampsDisplayValuesAndIgnoresAlpha) {
  const Image a = noise(24, 20, 5), b = noise(24, 20, 6);
  Image a4 = noise(24, 20, 7, 1, 4), b4 = noise(24, 20, 8, 1, 4);
  for (std::size_t i = 0; i < a.pixels.size() / 3; ++i)
    for (int c = 0; c < 3; ++c) {
      a4.pixels[i * 4 + c] = a.pixels[i * 3 + c];
      b4.pixels[i * 4 + c] = b.pixels[i * 3 + c];
    }
  a4.pixels[3] = std::numeric_limits<float>::quiet_NaN();  // alpha plays no part
  EXPECT_EQ(ldrFlip(a4, b4).map, ldrFlip(a, b).map);
  Image over = a, clipped = a;  // values past [0, 1] count as its ends
  for (float &v : over.pixels) v = v < 0.5f ? -3.0f : 7.0f;
  for (float &v : clipped.pixels) v = v < 0.5f ? 0.0f : 1.0f;
  EXPECT_EQ(ldrFlip(over, b).map, ldrFlip(clipped, b).map);
}

TEST(Flip, MeanIsTheArithmeticMeanOfTheMap) {
  const FlipResult r = ldrFlip(noise(19, 11, 9), noise(19, 11, 10));
  EXPECT_TRUE(r.width == 19 && r.height == 11 && r.map.size() == 19u * 11u);
  double sum = 0;
  for (const float v : r.map) sum += v;
  EXPECT_NEAR(r.mean, sum / r.map.size(), 1e-12);
  EXPECT_TRUE(std::ranges::all_of(r.map, [](float v) { return v >= 0 && v <= 1; }));
  EXPECT_GT(r.mean, 0.05);
}

TEST(Flip, BadInputIsNamed) {
  const Image a = filled(64, 32, 0.5f, 0.5f, 0.5f), b = filled(32, 32, 0.5f, 0.5f, 0.5f);
  const std::string size = thrownMessage([&] { ldrFlip(a, b); });
  EXPECT_TRUE(size.find("64x32") != size.npos && size.find("32x32") != size.npos) << size;
  EXPECT_NE(thrownMessage([&] { hdrFlip(b, a); }).find("32x32"), std::string::npos);
  const Image grey{32, 32, 1, std::vector<float>(32 * 32, 0.5f)};
  const std::string channels = thrownMessage([&] { ldrFlip(grey, b); });
  EXPECT_NE(channels.find("channels"), std::string::npos) << channels;
  EXPECT_NE(channels.find("has 1"), std::string::npos) << channels;
  Image nan = b;
  nan.at(3, 2, 1) = std::numeric_limits<float>::infinity();
  const std::string finite = thrownMessage([&] { ldrFlip(b, nan); });
  EXPECT_NE(finite.find("reference image: pixel (3, 2) channel 1 is not a finite number"),
            std::string::npos)
      << finite;
  EXPECT_NE(thrownMessage([&] { hdrFlip(nan, b); }).find("test image: pixel (3, 2)"),
            std::string::npos);
  const Image empty{0, 0, 3, {}};
  EXPECT_THROW(ldrFlip(empty, empty), std::invalid_argument);
  EXPECT_THROW(hdrFlipExposures(b, {2.0, 1.0, {}}), std::invalid_argument);  // start > stop
  EXPECT_THROW(hdrFlipExposures(b, {{}, {}, 0}), std::invalid_argument);
  EXPECT_THROW(hdrFlipExposures(b, {std::nan(""), {}, {}}), std::invalid_argument);
}

TEST(Flip, MatchesAnIndependentReDerivation) {
  // Reference numbers from a numpy re-derivation straight from the papers
  // (2D kernels, float64; NVIDIA's FLIP v1.6 agrees to 1e-8 on the means):
  // any stage or constant off moves them.
  const Image r = noise(32, 24, 21);
  Image t = noise(32, 24, 22);
  for (std::size_t i = 0; i < t.pixels.size(); ++i)
    t.pixels[i] = 0.7f * r.pixels[i] + 0.3f * t.pixels[i];
  const FlipResult ldr = ldrFlip(t, r);
  EXPECT_NEAR(ldr.mean, 0.2688223, 1e-6);
  EXPECT_NEAR(ldr.map[0], 0.3630065, 2e-6);
  EXPECT_NEAR(ldr.map[7 * 32 + 10], 0.1481756, 2e-6);
  Image hr = noise(32, 24, 23, 16), ht = noise(32, 24, 24, 16);
  for (int c = 0; c < 3; ++c) hr.at(6, 5, c) = 4000;
  for (std::size_t i = 0; i < ht.pixels.size(); ++i)
    ht.pixels[i] = 0.8f * hr.pixels[i] + 0.2f * ht.pixels[i];
  const FlipExposures e = hdrFlipExposures(hr);
  EXPECT_NEAR(e.start, -10.8824876, 1e-6);
  EXPECT_NEAR(e.stop, -1.9321739, 1e-6);
  EXPECT_EQ(e.count, 9);
  const FlipResult hdr = hdrFlip(ht, hr);
  EXPECT_NEAR(hdr.mean, 0.2052271, 1e-6);
  EXPECT_NEAR(hdr.map[5 * 32 + 6], 0.0963422, 2e-6);
}

TEST(Flip, FilteredColoursAreClampedToTheCube) {
  // A red and a blue pixel on black: the chroma kernels spread wider than
  // the achromatic one, so a few pixels away the filtered colour has chroma
  // without luminance, outside the RGB cube; FLIP clamps it back. Values
  // from the numpy re-derivation (without the clamp (14, 10) gives 0.023).
  const Image black = filled(21, 21, 0, 0, 0);
  Image test = black;
  test.at(10, 10, 0) = 1;
  test.at(11, 10, 2) = 1;
  const FlipResult r = ldrFlip(test, black);
  EXPECT_NEAR(r.mean, 0.0289622, 1e-6);
  EXPECT_NEAR(r.map[10 * 21 + 10], 0.7031645, 2e-6);
  EXPECT_NEAR(r.map[10 * 21 + 14], 0.0590974, 2e-6);
  EXPECT_NEAR(r.map[13 * 21 + 10], 0.0510744, 2e-6);
}

// The input the tone curve maps to 0.85, by bisection on the curve itself
// (not the quadratic the code solves).
double x85ByBisection() {
  double lo = 0, hi = 100;
  for (int i = 0; i < 200; ++i) {
    const double mid = (lo + hi) / 2;
    (flip::toneMapAces(mid) < 0.85 ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

TEST(Flip, AcesToneCurve) {
  EXPECT_EQ(flip::toneMapAces(0), 0);
  // 0.6^2 2.51 x^2 / (0.6^2 2.43 x^2) -> 1.033 for large x, clamped to 1.
  for (const double x : {1e3, 1e6, 1e300, std::numeric_limits<double>::infinity()})
    EXPECT_EQ(flip::toneMapAces(x), 1.0) << x;
  EXPECT_NEAR(flip::toneMapAces(1), (0.9036 + 0.018) / (0.8748 + 0.354 + 0.14), 1e-12);
  EXPECT_NEAR(flip::acesInverse(0.85), x85ByBisection(), 1e-12);
  EXPECT_NEAR(flip::toneMapAces(flip::acesInverse(0.3)), 0.3, 1e-12);
}

TEST(Flip, ExposuresOfAConstantReferenceByThePapersFormulas) {
  const Image ref = filled(16, 16, 0.5f, 1.0f, 2.0f);
  const double y = 0.2126 * 0.5 + 0.7152 * 1.0 + 0.0722 * 2.0;
  const FlipExposures e = hdrFlipExposures(ref);
  EXPECT_NEAR(e.start, std::log2(x85ByBisection() / y), 1e-9);  // log2(x85 / max Y)
  EXPECT_NEAR(e.stop, e.start, 1e-12);                          // log2(x85 / median Y)
  EXPECT_EQ(e.count, 2);                                        // max(2, ceil(0))
}

TEST(Flip, ExposuresSpanFromTheBrightestPixelToTheMedian) {
  Image ref = filled(8, 8, 1, 1, 1);  // Y = 1
  setPixel(ref, 3, 3, 64, 64, 64);
  const FlipExposures e = hdrFlipExposures(ref);
  EXPECT_NEAR(e.start, std::log2(x85ByBisection() / 64), 1e-9);
  EXPECT_NEAR(e.stop, std::log2(x85ByBisection()), 1e-9);
  EXPECT_EQ(e.count, 6);  // ceil(6 stops)
  // Rounding in the logarithms adds no exposure: 100 to 800 is 3 (+1e-15) stops.
  Image r3 = filled(8, 8, 100, 100, 100);
  setPixel(r3, 0, 0, 800, 800, 800);
  EXPECT_EQ(hdrFlipExposures(r3).count, 3);
  // The median is the sorted luminances' element n / 2 (the upper one for
  // even n, as NVIDIA's code takes it): Y = 1, 2, 4, 8 gives 4.
  Image four = filled(4, 1, 1, 1, 1);
  for (int x = 1; x < 4; ++x) setPixel(four, x, 0, float(1 << x), float(1 << x), float(1 << x));
  EXPECT_NEAR(hdrFlipExposures(four).stop, std::log2(x85ByBisection() / 4), 1e-9);
  // Options override each end and the count.
  const FlipExposures o = hdrFlipExposures(ref, {-1.0, {}, 3});
  EXPECT_EQ(o.start, -1.0);
  EXPECT_NEAR(o.stop, e.stop, 1e-12);
  EXPECT_EQ(o.count, 3);
}

TEST(Flip, ExposuresOfBlackAndMostlyBlackReferences) {
  // All black: nothing to place, so exposure 0 (start = stop = 0).
  const FlipExposures black = hdrFlipExposures(filled(8, 8, 0, 0, 0));
  EXPECT_TRUE(black.start == 0 && black.stop == 0 && black.count == 2);
  // Mostly black: the median is that of the lit pixels (here Y = 1, 2, 4).
  Image ref = filled(8, 8, 0, 0, 0);
  setPixel(ref, 0, 0, 1, 1, 1);
  setPixel(ref, 1, 0, 2, 2, 2);
  setPixel(ref, 2, 0, 4, 4, 4);
  ref.at(3, 0, 0) = -5;  // negative radiance counts as black
  const FlipExposures e = hdrFlipExposures(ref);
  EXPECT_NEAR(e.stop - e.start, 1, 1e-9);
  EXPECT_NEAR(e.stop, std::log2(x85ByBisection() / 2), 1e-9);
  EXPECT_EQ(e.count, 2);
  // And both stay finite through HDR-FLIP.
  const FlipResult r = hdrFlip(noise(8, 8, 11, 3), filled(8, 8, 0, 0, 0));
  for (const float v : r.map) ASSERT_TRUE(std::isfinite(v));
  EXPECT_GT(r.mean, 0);
}

TEST(Flip, HdrDifferencesAboveTheBrightestExposureStayFinite) {
  // The reference tops out at Y = 1; the test holds values a million times
  // brighter, which saturate at every exposure.
  const Image ref = noise(32, 32, 12, 1);
  Image test = ref;
  for (int y = 8; y < 12; ++y)
    for (int x = 8; x < 12; ++x) setPixel(test, x, y, 1e6f, 1e6f, 1e6f);
  const FlipResult r = hdrFlip(test, ref);
  // (NaN fails both comparisons.)
  EXPECT_TRUE(std::ranges::all_of(r.map, [](float v) { return v >= 0 && v <= 1; }));
  EXPECT_GT(r.map[10 * 32 + 10], 0.5f);
  // Exposures far past float's range (2^2000 overflows, 2^-2000 underflows).
  const FlipResult wild = hdrFlip(test, ref, {}, {-2000.0, 2000.0, 3});
  for (const float v : wild.map) ASSERT_TRUE(std::isfinite(v));
}

TEST(Flip, OneHdrExposureIsLdrFlipOfTheToneMappedSrgbImages) {
  const Image ref = noise(24, 24, 13, 4), test = noise(24, 24, 14, 4);
  const double exposure = -0.5;
  const auto display = [&](const Image &img) {
    Image out = img;
    for (float &v : out.pixels)
      v = float(flip::linearToSrgb(flip::toneMapAces(std::exp2(exposure) * v)));
    return out;
  };
  const FlipResult hdr = hdrFlip(test, ref, {}, {exposure, exposure, 1});
  const FlipResult ldr = ldrFlip(display(test), display(ref));
  for (std::size_t i = 0; i < hdr.map.size(); ++i) ASSERT_NEAR(hdr.map[i], ldr.map[i], 1e-4);
  // HDR-FLIP is the per-pixel maximum over its exposures.
  const FlipExposures e = hdrFlipExposures(ref);
  std::vector<float> largest(ref.pixels.size() / 3, 0.0f);
  for (int k = 0; k < e.count; ++k) {
    const double at = e.start + k * (e.stop - e.start) / (e.count - 1);
    const FlipResult one = hdrFlip(test, ref, {}, {at, at, 1});
    for (std::size_t i = 0; i < largest.size(); ++i) largest[i] = std::max(largest[i], one.map[i]);
  }
  EXPECT_EQ(hdrFlip(test, ref).map, largest);
}

TEST(Flip, HdrFlipIsNotSymmetric) {
  // The exposures come from the reference alone, so swapping the images
  // evaluates different exposures (LDR-FLIP is symmetric; HDR-FLIP is not).
  const Image dim = noise(16, 16, 15, 0.1f), bright = noise(16, 16, 16, 10);
  EXPECT_NE(hdrFlipExposures(dim).start, hdrFlipExposures(bright).start);
  EXPECT_NE(hdrFlip(dim, bright).mean, hdrFlip(bright, dim).mean);
}

TEST(Flip, MapImageIsMagma) {
  FlipResult r{{0.0f, 0.5f, 1.0f, 0.25f}, 4, 1, 0};
  const Image img = flipMapImage(r);
  ASSERT_TRUE(img.channels == 3 && img.width == 4 && img.height == 1);
  // magma's ends (near-black violet, pale yellow) and its middle (entry
  // 127.5, within 0.01 of the table's).
  const float expected[3][3] = {{0.001462f, 0.000466f, 0.013866f},
                                {0.716f, 0.215f, 0.475f},
                                {0.987053f, 0.991438f, 0.749504f}};
  for (int x = 0; x < 3; ++x)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(img.at(x, 0, c), expected[x][c], x == 1 ? 0.01f : 1e-6f);
  // Brighter with more error.
  const auto lum = [&](int x) {
    return rec709Luminance(img.at(x, 0, 0), img.at(x, 0, 1), img.at(x, 0, 2));
  };
  EXPECT_TRUE(lum(0) < lum(3) && lum(3) < lum(1) && lum(1) < lum(2));
}

}  // namespace
}  // namespace nuld
