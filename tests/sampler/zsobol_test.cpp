// ZSobol: the Morton order, the digit permutation (a bijection that keeps
// blocks), every pixel's set a net, every quad's union a finer net, and
// pixels, pairs and seeds decorrelated.
#include "sampler/sequences/zsobol.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <vector>

#include "tests/sampler/classic_set_oracles.h"

namespace nuld {
namespace {

std::vector<Point2> pixelSet(std::uint64_t seed, std::uint32_t pair, std::uint32_t px,
                             std::uint32_t py, std::uint32_t side, std::size_t spp) {
  std::vector<Point2> out(spp);
  zsobolSet(seed, pair, px, py, side, out);
  return out;
}

TEST(ZSobol, MortonCodeInterleavesXAtEvenBits) {
  EXPECT_EQ(mortonCode(0, 0), 0u);
  EXPECT_EQ(mortonCode(1, 0), 1u);
  EXPECT_EQ(mortonCode(0, 1), 2u);
  EXPECT_EQ(mortonCode(3, 3), 15u);
  EXPECT_EQ(mortonCode(5, 9), 0b10010011u);  // x 0101, y 1001
  EXPECT_EQ(mortonCode(0xffffffffu, 0), 0x5555555555555555ull);
}

// Every aligned block of 2^j indices (j of the digits' layout: even j, and
// odd j when the index has an odd number of bits) maps onto an aligned
// block, and the whole map is a bijection.
TEST(ZSobol, DigitPermutationIsABijectionThatKeepsBlocks) {
  for (int bits : {6, 7, 10}) {
    const std::uint64_t size = std::uint64_t(1) << bits;
    std::set<std::uint64_t> images;
    std::vector<std::uint64_t> image(size);
    for (std::uint64_t i = 0; i < size; ++i) images.insert(image[i] = zsobolIndex(3, 1, i, bits));
    EXPECT_EQ(images.size(), size);
    EXPECT_EQ(*images.rbegin(), size - 1);
    for (int j = bits % 2; j <= bits; j += 2)
      for (std::uint64_t start = 0; start < size; start += std::uint64_t(1) << j)
        for (std::uint64_t i = start; i < start + (std::uint64_t(1) << j); ++i)
          ASSERT_EQ(image[i] >> j, image[start] >> j) << "bits " << bits << " j " << j;
  }
  EXPECT_THROW(zsobolIndex(0, 0, 16, 4), std::invalid_argument);
}

// Each pixel's spp points are a (0, log2 spp, 2)-net; the four pixels of
// every aligned 2x2 quad together a (0, log2 spp + 2, 2)-net, and the 16 of
// every aligned 4x4 square a (0, log2 spp + 4, 2)-net.
TEST(ZSobol, PixelsQuadsAndSquaresAreNets) {
  const std::uint32_t side = 8;
  for (int l : {0, 1, 2, 3, 4}) {
    const std::size_t spp = std::size_t(1) << l;
    for (std::uint32_t pair : {0u, 5u})
      for (std::uint32_t y0 = 0; y0 < side; y0 += 4)
        for (std::uint32_t x0 = 0; x0 < side; x0 += 4) {
          std::vector<Point2> square;
          for (std::uint32_t qy = y0; qy < y0 + 4; qy += 2)
            for (std::uint32_t qx = x0; qx < x0 + 4; qx += 2) {
              std::vector<Point2> quad;
              for (std::uint32_t py = qy; py < qy + 2; ++py)
                for (std::uint32_t px = qx; px < qx + 2; ++px) {
                  const std::vector<Point2> p = pixelSet(11, pair, px, py, side, spp);
                  ASSERT_EQ(test::netFailure(p, l), "") << "pixel " << px << "," << py;
                  quad.insert(quad.end(), p.begin(), p.end());
                }
              ASSERT_EQ(test::netFailure(quad, l + 2), "") << "quad " << qx << "," << qy;
              square.insert(square.end(), quad.begin(), quad.end());
            }
          ASSERT_EQ(test::netFailure(square, l + 4), "") << "square " << x0 << "," << y0;
        }
  }
}

TEST(ZSobol, DeterministicAndDecorrelatedAcrossPixelsPairsAndSeeds) {
  const auto a = pixelSet(1, 0, 3, 5, 16, 16);
  EXPECT_EQ(a, pixelSet(1, 0, 3, 5, 16, 16));
  EXPECT_NE(a, pixelSet(1, 0, 4, 5, 16, 16));
  EXPECT_NE(a, pixelSet(1, 1, 3, 5, 16, 16));
  EXPECT_NE(a, pixelSet(2, 0, 3, 5, 16, 16));
  // Which quarter of its quad's block pixel (0, 0) takes is uniform over
  // seeds (one spp: the index is the permuted Morton code's last digit).
  std::vector<int> counts(4);
  for (int s = 0; s < 4000; ++s) ++counts[zsobolIndex(std::uint64_t(s), 0, 0, 6) & 3];
  EXPECT_LT(test::chiSquareUniform(counts), test::chiSquareCritical(4));
  // Two pairs order the same pixel's quarters independently: they agree on
  // about a quarter of the seeds.
  int same = 0;
  for (int s = 0; s < 4000; ++s)
    same += (zsobolIndex(std::uint64_t(s), 0, 0, 6) & 3) ==
            (zsobolIndex(std::uint64_t(s), 1, 0, 6) & 3);
  EXPECT_NEAR(same, 1000, 5 * std::sqrt(4000 * 0.1875));
}

// The scrambling is uniform at every depth: over seeds, a point's digit
// 6 (inside the second hashed subtree of the tree) and its position within
// its finest stratum (the tail below the image's 2 log2(side) + l digits)
// are uniform.
TEST(ZSobol, ScramblingIsUniformAtEveryDepth) {
  std::vector<int> digit(2), within(16);
  for (int s = 0; s < 4000; ++s) {
    const Point2 p = pixelSet(std::uint64_t(s), 0, 2, 1, 4, 4)[1];  // 8 digits
    ++digit[int(p.x * 128) & 1];
    ++within[int(std::fmod(p.y * 256, 1.0) * 16)];
  }
  EXPECT_LT(test::chiSquareUniform(digit), test::chiSquareCritical(2));
  EXPECT_LT(test::chiSquareUniform(within), test::chiSquareCritical(16));
}

// N not a power of two: the first N points of the pixel's 2^l block.
TEST(ZSobol, OtherSampleCountsTakeThePrefixOfTheBlock) {
  const auto eight = pixelSet(4, 2, 1, 6, 8, 8), five = pixelSet(4, 2, 1, 6, 8, 5);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(five[i], eight[i]);
  EXPECT_EQ(pixelSet(4, 2, 0, 0, 1, 1).size(), 1u);
}

TEST(ZSobol, RefusesImagesWhoseIndexNeedsMoreThan32Bits) {
  EXPECT_NO_THROW(pixelSet(0, 0, 100, 200, 1 << 14, 16));
  EXPECT_THROW(pixelSet(0, 0, 100, 200, 1 << 14, 32), std::invalid_argument);
  EXPECT_THROW(pixelSet(0, 0, 1, 1, 12, 4), std::invalid_argument);  // not a power of two
  EXPECT_THROW(pixelSet(0, 0, 16, 1, 16, 4), std::invalid_argument);
}

}  // namespace
}  // namespace nuld
