#pragma once
// ZSobol (Ahmed and Wonka 2020, "Screen-Space Blue-Noise Diffusion of Monte
// Carlo Sampling Error via Hierarchical Ordering of Pixels", as pbrt-v4's
// ZSobolSampler builds it). One Owen-scrambled 2D Sobol sequence serves the
// whole image: pixel (px, py) takes the block of 2^l indices (l = log2 of
// the samples per pixel, rounded up) at its Morton code, so every pixel's
// points are a (0, l, 2)-net and the 4^j pixels of every aligned 2^j x 2^j
// square together form a (0, l + 2j, 2)-net. Before the Sobol lookup the
// index's base-4 digits are randomly permuted, each by a permutation chosen
// from the digits above it, so the order in which a quad's pixels take the
// quad's block is random at every level: neighbouring pixels get
// complementary, decorrelated sets, which moves the error to high
// frequencies on the screen. Screen-space only: a pixel's set depends on
// the pixel and the image, so there is no set of N of its own.

#include <cstdint>
#include <span>

#include "sampler/point.h"

namespace nuld {

// The Z-order (Morton) code: x's bits at the even positions, y's at the odd.
std::uint64_t mortonCode(std::uint32_t x, std::uint32_t y);

// The Sobol index of Morton index `mortonIndex` < 2^indexBits (the pixel's
// Morton code, then its log2 spp sample bits). From the most significant,
// each base-4 digit is replaced by its image under one of the 24
// permutations of {0, 1, 2, 3}, chosen by a hash of the digits above it, its
// position, `pair` and `seed`; when indexBits is odd the last digit is a
// base-2 digit flipped by such a hash (pbrt's layout). A bijection of
// [0, 2^indexBits) that maps the block of every prefix onto an aligned block.
std::uint64_t zsobolIndex(std::uint64_t seed, std::uint32_t pair, std::uint64_t mortonIndex,
                          int indexBits);

// The N = out.size() points of pixel (px, py) for dimension pair `pair`, in
// an image whose sides are at most `imageSide`, a power of two (px, py <
// imageSide): sample s is Sobol point zsobolIndex((Morton(px, py) << l) | s)
// of dimensions (0, 1), each coordinate Owen-scrambled by a key of (seed,
// pair, coordinate) over all 2 log2(imageSide) + l digits that tell the
// image's points apart. l = ceil(log2 N); when N is not a power of two the
// pixel takes the first N of its 2^l indices (a part of the net, as pbrt
// does). The index must fit 32 bits: 2 log2(imageSide) + l <= 32, or
// std::invalid_argument. About a dozen hashes a point (1.3 us for 16
// points, 22 us for 256: 6 to 8 times an Owen-Sobol set of generateSet, as
// every point walks the image-wide scrambling tree); thread-safe, no state
// kept between calls.
void zsobolSet(std::uint64_t seed, std::uint32_t pair, std::uint32_t px, std::uint32_t py,
               std::uint32_t imageSide, std::span<Point2> out);

}  // namespace nuld
