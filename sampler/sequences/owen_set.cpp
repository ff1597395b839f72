#include "sampler/sequences/owen_set.h"

#include <array>
#include <stdexcept>
#include <vector>

#include "sampler/sequences/scrambling.h"

namespace nuld {

void owenScrambleSet(std::uint64_t seed, int d, std::span<const std::uint32_t> bits,
                     std::span<Point2> out, double Point2::*coordinate) {
  if (d < 0 || d >= 32 || bits.size() != out.size() || bits.size() > (std::size_t(1) << d))
    throw std::invalid_argument("owenScrambleSet: needs n <= 2^d points, d < 32");
  const OwenTree tree(seed);
  if (d == 0) {  // one point: every digit sits under the empty prefix
    if (!out.empty()) out[0].*coordinate = (bits[0] ^ tree.tailFlips(0, 0)) * 0x1.0p-32;
    return;
  }
  // flips[(1 << l) - 1 + q]: the flips of digits 0..l under the l-digit
  // prefix q; all[p]: every flip of a point with d-digit prefix p, tail
  // included. On the stack for the renderer's small sets (n <= 256), in
  // per-thread buffers beyond.
  constexpr int kStackLevels = 8;
  std::array<std::uint32_t, (1 << kStackLevels) - 1> smallFlips;
  std::array<std::uint32_t, 1 << kStackLevels> smallAll;
  thread_local std::vector<std::uint32_t> largeFlips, largeAll;
  const bool small = d <= kStackLevels;
  if (!small) {
    largeFlips.resize((std::size_t(1) << d) - 1);
    largeAll.resize(std::size_t(1) << d);
  }
  std::uint32_t *const flips = small ? smallFlips.data() : largeFlips.data();
  std::uint32_t *const all = small ? smallAll.data() : largeAll.data();
  for (int l = 0; l < d; ++l)
    for (std::uint64_t q = 0; q < (std::uint64_t(1) << l); ++q)
      flips[(std::size_t(1) << l) - 1 + q] =
          tree.digitFlip(q, l) | (l == 0 ? 0u : flips[(std::size_t(1) << (l - 1)) - 1 + (q >> 1)]);
  // The tails by prefix, one hash per pair of siblings (2^d < 2n, so fewer
  // hashes than one per point).
  const std::uint32_t *const deepest = flips + (std::size_t(1) << (d - 1)) - 1;
  for (std::uint64_t q = 0; q < (std::uint64_t(1) << (d - 1)); ++q) {
    const auto tails = tree.siblingTailFlips(q, d);
    all[2 * q] = deepest[q] | tails[0];
    all[2 * q + 1] = deepest[q] | tails[1];
  }
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i].*coordinate = (bits[i] ^ all[bits[i] >> (32 - d)]) * 0x1.0p-32;
}

}  // namespace nuld
