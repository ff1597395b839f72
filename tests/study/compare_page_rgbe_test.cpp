// The comparison page's RGBE encoding (tools/study/compare_page.h), decoded
// as the page's viewer decodes it: within 0.4 % of each pixel's largest
// channel over 1e-30 to 1e38, and black, not garbage, for what a render
// should never hold (negative, NaN); the page's own test
// (compare_page_test.py) checks it in a browser.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "tools/study/compare_page.h"

namespace nuld::study {
namespace {

// viewer.js's decodeRgbe for one pixel.
std::vector<double> decode(const std::string &bytes, std::size_t p) {
  const auto b = [&](std::size_t k) {
    return double(static_cast<unsigned char>(bytes[4 * p + k]));
  };
  if (b(3) == 0) return {0, 0, 0};
  const double f = std::ldexp(1.0, int(b(3)) - 136);
  return {(b(0) + 0.5) * f, (b(1) + 0.5) * f, (b(2) + 0.5) * f};
}

TEST(CompareRgbe, WithinItsPrecisionOverTheWholeRange) {
  std::vector<float> pixels;
  for (double v = 1e-30; v < 1e38; v *= 7.3) {
    pixels.insert(pixels.end(), {float(v), float(v * 0.31), float(v * 0.002)});
  }
  const int n = int(pixels.size() / 3);
  const Image img{n, 1, 3, pixels};
  const std::string bytes = encodeRgbe(img);
  ASSERT_EQ(bytes.size(), 4u * std::size_t(n));
  for (int p = 0; p < n; ++p) {
    const std::vector<double> d = decode(bytes, std::size_t(p));
    const double largest = pixels[3 * std::size_t(p)];
    for (int k = 0; k < 3; ++k)
      EXPECT_LE(std::abs(d[std::size_t(k)] - pixels[3 * std::size_t(p) + std::size_t(k)]),
                0.004 * largest)
          << "pixel " << p << " channel " << k << " of " << largest;
  }
}

TEST(CompareRgbe, BlackNegativeNanAndInfinite) {
  const float nan = std::numeric_limits<float>::quiet_NaN(),
              inf = std::numeric_limits<float>::infinity();
  const Image img{4, 1, 3, {0, 0, 0, -1, -2, -3, nan, 0.5f, nan, inf, 1, 0}};
  const std::string bytes = encodeRgbe(img);
  EXPECT_EQ(decode(bytes, 0), (std::vector<double>{0, 0, 0}));
  EXPECT_EQ(decode(bytes, 1), (std::vector<double>{0, 0, 0}));
  const std::vector<double> half = decode(bytes, 2);
  EXPECT_LE(half[0], 0.004 * 0.5);  // NaN as 0, within the precision of 0.5
  EXPECT_NEAR(half[1], 0.5, 0.002);
  const std::vector<double> big = decode(bytes, 3);
  EXPECT_TRUE(std::isfinite(big[0]));
  EXPECT_GT(big[0], 1e37);
}

// A grey (one-channel) image is shown grey.
TEST(CompareRgbe, OneChannelIsGrey) {
  const Image img{1, 1, 1, {0.25f}};
  const std::vector<double> d = decode(encodeRgbe(img), 0);
  EXPECT_NEAR(d[0], 0.25, 0.001);
  EXPECT_EQ(d[0], d[1]);
  EXPECT_EQ(d[1], d[2]);
}

}  // namespace
}  // namespace nuld::study
