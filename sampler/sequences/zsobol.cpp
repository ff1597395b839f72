#include "sampler/sequences/zsobol.h"

#include <array>
#include <bit>
#include <stdexcept>
#include <string>
#include <vector>

#include "sampler/sequences/rng.h"
#include "sampler/sequences/sobol.h"

namespace nuld {
namespace {

// The 24 permutations of {0, 1, 2, 3}, in lexicographic order.
constexpr auto kPermutations = [] {
  std::array<std::array<std::uint8_t, 4>, 24> table{};
  int k = 0;
  for (std::uint8_t a = 0; a < 4; ++a)
    for (std::uint8_t b = 0; b < 4; ++b)
      for (std::uint8_t c = 0; c < 4; ++c)
        if (a != b && a != c && b != c) table[k++] = {a, b, c, std::uint8_t(6 - a - b - c)};
  return table;
}();

// The digit permutations of one (seed, pair). Applied to the digits of an
// index at bit positions [low, high) (the others kept): base-4 digits from
// the top down, then, when high - low is odd, a base-2 digit at `low`. A
// digit's permutation is a pure function of the key, its position, its
// width and the original digits above it, so ranges split at a digit
// boundary permute as the whole range does. Each level remembers its last
// hash: a pixel's samples, taken in order, share the digits above most
// levels, so each node of the digit tree is hashed about once.
class DigitPermutation {
 public:
  DigitPermutation(std::uint64_t seed, std::uint32_t pair)
      : key_(mix64(mix64(seed ^ 0x7a736f626f6cull) + 0x9e3779b97f4a7c15ull * (pair + 1))) {
    lastHigher_.fill(~0ull);  // no index has these digits above a level
  }

  std::uint64_t operator()(std::uint64_t index, int low, int high) {
    std::uint64_t out = index;
    for (int shift = high - 2; shift >= low - 1; shift -= 2) {
      const int width = shift >= low ? 2 : 1, at = shift >= low ? shift : low;
      const std::uint64_t higher = index >> (at + width);
      if (higher != lastHigher_[at]) {
        lastHigher_[at] = higher;
        lastHash_[at] = mix64(key_ + 0x9e3779b97f4a7c15ull *
                                         ((higher << 7) | (std::uint64_t(at) << 1) | (width & 1)));
      }
      const std::uint64_t h = lastHash_[at];
      const auto digit = std::uint32_t(index >> at) & ((1u << width) - 1);
      const std::uint32_t image =
          width == 2 ? kPermutations[(h >> 32) * 24 >> 32][digit] : digit ^ std::uint32_t(h >> 63);
      out = (out & ~(std::uint64_t((1u << width) - 1) << at)) | (std::uint64_t(image) << at);
    }
    return out;
  }

 private:
  std::uint64_t key_;
  std::array<std::uint64_t, 33> lastHigher_, lastHash_{};  // by the digit's bit position
};

// Nested uniform Owen scrambling of the `digits` leading digits of a
// coordinate, then an independent tail below them, with one hash per
// 6-level subtree of the scrambling tree rather than one per digit
// (OwenTree's below its top 6 levels): the flip of digit 6b + t under its
// prefix is bit (2^t - 1 + the t digits after 6b) of the hash of the
// 6b-digit prefix, so every node still has its own random bit. The image's
// points share no prefix a set could tabulate (owen_set.h), so each point
// walks all 20 to 32 levels: 4 to 6 hashes instead of 15 to 27.
class BlockedOwenTree {
 public:
  BlockedOwenTree(std::uint64_t seed, std::uint32_t pair, int coordinate)
      : key_(hash3(seed, pair, 0x20736f626f6cull + coordinate)), root_(hashOf(0, 0)) {}

  std::uint32_t scramble(std::uint32_t v, int digits) const {
    // Digit j of v and of the flips at bit 63 - j (zeros past digit 31).
    const std::uint64_t wide = std::uint64_t(v) << 32;
    std::uint64_t flips = 0;
    for (int top = 0; top < digits; top += 6) {
      const std::uint64_t h = top == 0 ? root_ : hashOf(v >> (32 - top), top);
      const auto c = std::uint32_t(wide << top >> 58);  // the 6 digits from `top`
      const auto node = [&](int t) { return h >> ((1u << t) - 1 + (c >> (6 - t))) & 1; };
      const std::uint64_t chunk =
          node(0) << 5 | node(1) << 4 | node(2) << 3 | node(3) << 2 | node(4) << 1 | node(5);
      flips |= chunk << (58 - top);
    }
    auto f = std::uint32_t(flips >> 32);
    // The digits from `digits` on: the tail of the prefix (length 63 tags
    // it: no subtree hash has that length).
    if (digits < 32)
      f = (f & ~(0xffffffffu >> digits)) |
          std::uint32_t(hashOf(digits == 0 ? 0 : v >> (32 - digits), 63)) >> digits;
    return v ^ f;
  }

 private:
  std::uint64_t hashOf(std::uint64_t prefix, int length) const {
    return mix64(key_ + 0x9e3779b97f4a7c15ull * ((prefix << 6) | std::uint64_t(length)));
  }
  std::uint64_t key_, root_;
};

}  // namespace

std::uint64_t mortonCode(std::uint32_t x, std::uint32_t y) {
  // Spreads 32 bits to the even positions of 64 by the usual masks.
  const auto spread = [](std::uint64_t v) {
    v = (v | (v << 16)) & 0x0000ffff0000ffffull;
    v = (v | (v << 8)) & 0x00ff00ff00ff00ffull;
    v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0full;
    v = (v | (v << 2)) & 0x3333333333333333ull;
    v = (v | (v << 1)) & 0x5555555555555555ull;
    return v;
  };
  return spread(x) | (spread(y) << 1);
}

std::uint64_t zsobolIndex(std::uint64_t seed, std::uint32_t pair, std::uint64_t mortonIndex,
                          int indexBits) {
  if (indexBits < 0 || indexBits > 32 || (mortonIndex >> indexBits) != 0)
    throw std::invalid_argument("zsobolIndex: index beyond its " + std::to_string(indexBits) +
                                " bits (at most 32)");
  return DigitPermutation(seed, pair)(mortonIndex, 0, indexBits);
}

void zsobolSet(std::uint64_t seed, std::uint32_t pair, std::uint32_t px, std::uint32_t py,
               std::uint32_t imageSide, std::span<Point2> out) {
  if (out.empty()) return;
  if (!std::has_single_bit(imageSide) || px >= imageSide || py >= imageSide)
    throw std::invalid_argument("zsobol: pixel (" + std::to_string(px) + ", " + std::to_string(py) +
                                ") in an image of side " + std::to_string(imageSide) +
                                " (a power of two above both)");
  const int l = std::bit_width(out.size() - 1);  // ceil(log2 N)
  const int bits = 2 * std::countr_zero(imageSide) + l;
  if (bits > 32)
    throw std::invalid_argument("zsobol: " + std::to_string(out.size()) +
                                " samples per pixel in an image of side " +
                                std::to_string(imageSide) + " need a Sobol index of " +
                                std::to_string(bits) + " bits; at most 32");
  DigitPermutation permute(seed, pair);
  const std::uint64_t pixel = mortonCode(px, py) << l, low = (std::uint64_t(1) << l) - 1;
  // The pixel's digits are permuted once: they and the digits above them
  // are the same for all its samples. Sobol points are linear in the index
  // bits (XOR), so the block's part is looked up once too.
  const std::uint64_t block = permute(pixel, l, bits) & ~low;
  const std::uint32_t blockX = sobolBits(block, 0), blockY = sobolBits(block, 1);
  thread_local std::vector<std::uint32_t> partX, partY;  // the sample parts' Sobol points
  partX.resize(std::size_t(1) << l);
  partY.resize(partX.size());
  sobolRun(0, partX);
  sobolRun(1, partY);
  const BlockedOwenTree treeX(seed, pair, 0), treeY(seed, pair, 1);
  for (std::size_t s = 0; s < out.size(); ++s) {
    const std::uint64_t sample = permute(pixel | s, 0, l) & low;
    out[s] = {treeX.scramble(blockX ^ partX[sample], bits) * 0x1.0p-32,
              treeY.scramble(blockY ^ partY[sample], bits) * 0x1.0p-32};
  }
}

}  // namespace nuld
