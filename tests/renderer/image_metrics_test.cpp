#include "renderer/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace nuld
