#include "renderer/image_metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "renderer/render.h"
#include "sampler/io/image_io.h"
#include "sampler/sequences/rng.h"
#include "tests/common/temp_dir.h"

namespace nuld {
namespace {

Image filled(int w, int h, float v) {
  return Image{w, h, 3, std::vector<float>(std::size_t(w) * h * 3, v)};
}

TEST(ImageMetrics, MseAndRelMseByHand) {
  Image ref = filled(2, 1, 1.0f), img = filled(2, 1, 1.0f);
  img.at(1, 0, 2) = 3.0f;  // one channel off by 2
  const ImageError e = compareImages(img, ref);
  EXPECT_DOUBLE_EQ(e.mse, 4.0 / 6);
  EXPECT_DOUBLE_EQ(e.relmse, 4.0 / 1.01 / 6);
  EXPECT_EQ(compareImages(ref, ref).mse, 0);
}

// The winsorized MSE and the top pixels' share against sorting every
// pixel's error: the k = floor(0.001 x pixels) largest count as the
// (k + 1)-th; one firefly among small errors rules the MSE, not it.
TEST(ImageMetrics, WinsorizedMseAgainstASortByHand) {
  const int w = 100, h = 41;  // 4100 pixels: k = 4
  Image ref = filled(w, h, 0.5f), img = ref;
  Rng rng(7);
  for (float &v : img.pixels) v += float(0.1 * (rng.uniform() - 0.5));
  img.at(3, 4, 1) = 1000.0f;  // a firefly
  img.at(50, 20, 0) = -40.0f;
  const ImageError e = compareImages(img, ref);
  std::vector<double> pixel;
  double all = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double p = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = double(img.at(x, y, c)) - ref.at(x, y, c);
        p += d * d;
      }
      pixel.push_back(p);
      all += p;
    }
  std::sort(pixel.rbegin(), pixel.rend());
  const std::size_t k = 4;
  double top = 0, clipped = 0;
  for (std::size_t i = 0; i < pixel.size(); ++i) {
    if (i < k) top += pixel[i];
    clipped += i < k ? pixel[k] : pixel[i];
  }
  EXPECT_NEAR(e.mse, all / (3.0 * w * h), 1e-12 * e.mse);
  EXPECT_NEAR(e.winsorized, clipped / (3.0 * w * h), 1e-12 * e.winsorized);
  EXPECT_NEAR(e.topShare, top / all, 1e-12);
  EXPECT_GT(e.topShare, 0.99) << "the firefly is nearly all of the MSE";
  EXPECT_LT(e.winsorized, 1e-3 * e.mse);
  // No error: no share; fewer pixels than k + 1 keep their MSE.
  EXPECT_EQ(compareImages(ref, ref).topShare, 0);
  const Image one = filled(1, 1, 2.0f);
  EXPECT_EQ(compareImages(one, filled(1, 1, 1.0f)).winsorized,
            compareImages(one, filled(1, 1, 1.0f)).mse);
}

// The low-pass against a brute-force 2D convolution with the product
// kernel, renormalized over the neighbours inside the image (which the
// separable passes equal, the in-image neighbourhood being a rectangle).
TEST(ImageMetrics, GaussianBlurIsTheRenormalizedProductKernel) {
  const int w = 9, h = 6;
  std::vector<double> v(std::size_t(w) * h);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::sin(1.7 * double(i)) + 0.1 * double(i % 5);
  for (const double sigma : {0.5, 1.0, 2.0}) {
    const std::vector<double> blurred = gaussianBlur(v, w, h, sigma);
    const int r = std::max(1, int(std::ceil(3 * sigma)));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double sum = 0, weight = 0;
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx) {
            if (x + dx < 0 || x + dx >= w || y + dy < 0 || y + dy >= h) continue;
            const double g = std::exp(-0.5 * (dx * dx + dy * dy) / (sigma * sigma));
            sum += g * v[std::size_t(y + dy) * w + x + dx];
            weight += g;
          }
        EXPECT_NEAR(blurred[std::size_t(y) * w + x], sum / weight, 1e-12) << x << "," << y;
      }
  }
}

// A uniform error is all the viewer sees (screen = mse); a pixel-by-pixel
// alternating error of the same MSE mostly averages away; the Gaussian of
// one pixel keeps exp(-2 pi^2 sigma^2 f^2)^2 of a frequency f's power
// (Nyquist: f = 1/2 per axis, so about 0.005 inside the image).
TEST(ImageMetrics, ScreenErrorSeesLowFrequenciesAndNotHighOnes) {
  const Image ref = filled(32, 32, 1.0f);
  const ImageError flat = compareImages(filled(32, 32, 1.25f), ref);
  EXPECT_NEAR(flat.screen, flat.mse, 1e-12);
  Image checker = ref;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x)
      for (int c = 0; c < 3; ++c) checker.at(x, y, c) = (x + y) % 2 ? 1.25f : 0.75f;
  const ImageError hf = compareImages(checker, ref);
  EXPECT_NEAR(hf.mse, flat.mse, 1e-12);
  EXPECT_LT(hf.screen, 0.02 * hf.mse);
  EXPECT_GT(hf.screen, 0.0);
}

// The spectrum against a brute-force DFT of the centred power-of-two crop
// (an 8 x 8 square out of 11 x 9), radially averaged the same way.
TEST(ImageMetrics, ErrorSpectrumIsTheRadiallyAveragedDft) {
  const Image ref = filled(11, 9, 0.5f);
  Image img = ref;
  Rng rng(5);
  for (float &v : img.pixels) v += float(rng.uniform() - 0.5);
  const std::vector<double> spectrum = errorPowerSpectrum(img, ref);
  const int n = 8, x0 = 1, y0 = 0;
  std::vector<double> sum(n / 2 + 1, 0.0), count(n / 2 + 1, 0.0);
  for (int ky = 0; ky < n; ++ky)
    for (int kx = 0; kx < n; ++kx) {
      std::complex<double> f = 0;
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
          f += (img.luminance(x0 + x, y0 + y) - ref.luminance(x0 + x, y0 + y)) *
               std::polar(1.0, -2 * std::numbers::pi * (kx * x + ky * y) / n);
      const double fx = kx <= n / 2 ? kx : kx - n, fy = ky <= n / 2 ? ky : ky - n;
      const auto r = std::size_t(std::lround(std::hypot(fx, fy)));
      if (r > std::size_t(n / 2)) continue;
      sum[r] += std::norm(f) / (n * n);
      count[r] += 1;
    }
  ASSERT_EQ(spectrum.size(), sum.size());
  for (std::size_t r = 0; r < sum.size(); ++r)
    EXPECT_NEAR(spectrum[r], sum[r] / count[r], 1e-12 * (1 + sum[r])) << r;
}

// White error is flat at its variance; a stripe pattern of 8 cycles peaks
// at radius 8; an image with a side under 2 has no spectrum.
TEST(ImageMetrics, ErrorSpectrumOfWhiteNoiseAndOfAStripe) {
  const Image ref = filled(64, 64, 1.0f);
  Image noise = ref;
  Rng rng(11);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const float e = float(rng.uniform() - 0.5);  // variance 1/12
      for (int c = 0; c < 3; ++c) noise.at(x, y, c) += e;
    }
  const std::vector<double> white = errorPowerSpectrum(noise, ref);
  double low = 0, high = 0;
  for (int r = 1; r <= 10; ++r) low += white[r] / 10;
  for (int r = 22; r <= 31; ++r) high += white[r] / 10;
  EXPECT_NEAR(low, 1.0 / 12, 0.2 / 12);
  EXPECT_NEAR(high, 1.0 / 12, 0.1 / 12);
  Image stripe = ref;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c)
        stripe.at(x, y, c) += float(0.1 * std::cos(2 * std::numbers::pi * 8 * x / 64));
  const std::vector<double> peak = errorPowerSpectrum(stripe, ref);
  EXPECT_EQ(std::max_element(peak.begin(), peak.end()) - peak.begin(), 8);
  EXPECT_TRUE(errorPowerSpectrum(filled(1, 5, 0.0f), filled(1, 5, 0.0f)).empty());
}

TEST(ImageMetrics, NonFinitePixelsAreCountedNotAveraged) {
  Image ref = filled(2, 2, 0.5f), img = filled(2, 2, 0.5f);
  img.at(0, 1, 0) = std::nanf("");
  const ImageError e = compareImages(img, ref);
  EXPECT_EQ(e.nonFinitePixels, 1u);
  EXPECT_EQ(e.mse, 0);
}

TEST(ImageMetrics, SizeMismatchIsAClearError) {
  try {
    compareImages(filled(2, 2, 0), filled(3, 2, 0));
    FAIL();
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("2x2 vs reference 3x2"), std::string::npos);
  }
}

TEST(ImageMetrics, ErrorMapGrowsWithTheErrorAndToneMapIsBounded) {
  Image ref = filled(3, 1, 1.0f), img = filled(3, 1, 1.0f);
  img.at(1, 0, 0) = 1.1f;
  img.at(2, 0, 0) = 5.0f;
  const Image map = errorMap(img, ref);
  const auto brightness = [&](int x) {
    return map.at(x, 0, 0) + map.at(x, 0, 1) + map.at(x, 0, 2);
  };
  EXPECT_LT(brightness(0), brightness(1));
  EXPECT_LT(brightness(1), brightness(2));
  Image hdr = filled(2, 1, 1e6f);
  hdr.at(0, 0, 0) = std::nanf("");
  for (float v : toneMap(hdr).pixels) EXPECT_TRUE(v >= 0 && v <= 1);
}

// A render's files say how they were made: the attributes written with the
// EXR and its PNG preview read back, in order, with their values.
TEST(ImageMetrics, RenderFilesCarryTheirAttributes) {
  const test::TempDir dir;
  const Image img{4, 3, 3, std::vector<float>(36, 0.25f)};
  Scene scene{EmbreeScene({}), {}, std::nullopt, {}};
  scene.lobeChoice = LobeChoice::Uniform;
  scene.environment.emplace(Image{2, 1, 3, std::vector<float>(6, 1.0f)}, 1.0, 0.0, "grey",
                            Vec3{0, 1, 0}, PixelWeight::LuminanceCompensated);
  RenderSettings s;
  s.width = 4, s.height = 3, s.spp = 8;
  s.integrator = IntegratorKind::Direct;
  RenderStats stats;
  stats.seconds = 1.5;
  const ImageAttributes attributes = renderAttributes("default", scene, s, "sobol", 7, stats);
  const std::string exr = (dir.path() / "r.exr").string();
  writeRender(exr, img, attributes);
  for (const std::string &path : {exr, (dir.path() / "r.png").string()}) {
    const ImageAttributes back = readImageAttributes(path);
    EXPECT_EQ(back.size(), attributes.size()) << path;
    for (const auto &[name, value] : attributes)
      EXPECT_NE(std::find(back.begin(), back.end(), std::pair{name, value}), back.end())
          << path << " " << name << " = " << value;
  }
  const auto has = [&](const std::string &name, const std::string &value) {
    return std::find(attributes.begin(), attributes.end(), std::pair{name, value}) !=
           attributes.end();
  };
  EXPECT_TRUE(has("nuld:backend", "sobol"));
  EXPECT_TRUE(has("nuld:spp", "8"));
  EXPECT_TRUE(has("nuld:seed", "7"));
  EXPECT_TRUE(has("nuld:integrator", "direct"));
  EXPECT_TRUE(has("nuld:lobe_choice", "uniform"));
  EXPECT_TRUE(has("nuld:env_importance", "luminance-compensated"));
  EXPECT_TRUE(has("nuld:lobe_mix", "1"));  // MIS: the sampling pdf
  EXPECT_TRUE(has("nuld:render_seconds", "1.5"));
  EXPECT_THROW(readImageAttributes((dir.path() / "absent.exr").string()), std::runtime_error);
}

}  // namespace
}  // namespace nuld
