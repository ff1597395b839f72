#include "sampler/sequences/sequence.h"

#include <array>
#include <stdexcept>
#include <vector>

#include "sampler/io/pointset_metadata.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/scrambling.h"
#include "sampler/sequences/sobol.h"

namespace nuld {

std::uint32_t nthPrime(std::uint32_t p) {
  static const std::vector<std::uint32_t> primes = [] {
    std::vector<std::uint32_t> out;
    for (std::uint32_t c = 2; out.size() < 1000; ++c) {
      bool prime = true;
      for (std::uint32_t q : out) {
        if (q * q > c) break;
        if (c % q == 0) {
          prime = false;
          break;
        }
      }
      if (prime) out.push_back(c);
    }
    return out;
  }();
  if (p >= primes.size()) throw std::out_of_range("Halton: too many dimensions");
  return primes[p];
}

std::uint64_t dimensionSeed(std::uint64_t seed, std::uint32_t instance, std::uint32_t dim) {
  // mix64 is a bijection, so distinct (instance, dim) under one seed give
  // distinct inputs to the last mix; other seeds land elsewhere at random.
  return mix64(mix64(seed) + 0x9e3779b97f4a7c15ull * ((std::uint64_t(instance) << 32) | dim));
}

namespace {

// Digits that tell the first n points apart: ceil(log_base n).
int distinctDigits(std::size_t n, std::uint32_t base) {
  int d = 0;
  for (std::uint64_t span = 1; span < n; span *= base) ++d;
  return d;
}

// distinct < 0: every digit scrambled separately; otherwise the number of
// leading digits that tell the set's points apart (see owenScramble).
double sample(const SequenceOptions &o, std::uint64_t index, std::uint32_t dim,
              std::uint32_t instance, int distinct) {
  // One independent seed per (instance, dimension).
  const std::uint64_t seed = dimensionSeed(o.seed, instance, dim);
  switch (o.kind) {
    case SequenceKind::Random: return independentSample(hashCombine(o.seed, instance), index, dim);
    case SequenceKind::Sobol: {
      std::uint32_t bits = sobolBits(index, dim);
      if (o.scramble == Scramble::Owen)
        bits = owenScramble(bits, seed, distinct < 0 ? 32 : distinct);
      if (o.scramble == Scramble::Shift) bits = digitalShift(bits, seed);
      const double x = bits * 0x1.0p-32;
      return o.scramble == Scramble::CranleyPatterson ? cranleyPatterson(x, seed) : x;
    }
    case SequenceKind::Halton: {
      const std::uint32_t base = nthPrime(dim);
      const DigitRandomization r = o.scramble == Scramble::Owen    ? DigitRandomization::Owen
                                   : o.scramble == Scramble::Shift ? DigitRandomization::Shift
                                                                   : DigitRandomization::None;
      const double x = radicalInverse(index, base, r, seed, distinct < 0 ? 64 : distinct);
      return o.scramble == Scramble::CranleyPatterson ? cranleyPatterson(x, seed) : x;
    }
  }
  return 0;
}

// One coordinate of an Owen-scrambled Sobol set of n = out.size() points,
// the same values as sample() with `distinct` = d = ceil(log2 n) digits, with
// far fewer hashes: sample() walks the scrambling tree from the root for
// every point, while the n points share their short prefixes (level l has at
// most 2^l). Here the flips of the d leading digits are computed once per
// prefix, in a table by level; each point then adds its own tail. The
// renderer's sobol backend scrambles every pixel and pair afresh with it.
void owenSobolCoordinate(std::uint64_t seed, std::uint32_t dim, int d, std::span<Point2> out,
                         double Point2::*coordinate) {
  const OwenTree tree(seed);
  // flips[(1 << l) - 1 + q]: the flips of digits 0..l under the l-digit
  // prefix q; all[p]: every flip of a point with d-digit prefix p, tail
  // included; bits: the points' Sobol integers. On the stack for the
  // renderer's small sets (spp <= 256), in per-thread buffers beyond.
  constexpr int kStackLevels = 8;
  std::array<std::uint32_t, (1 << kStackLevels) - 1> smallFlips;
  std::array<std::uint32_t, 1 << kStackLevels> smallAll, smallBits;
  thread_local std::vector<std::uint32_t> largeFlips, largeAll, largeBits;
  const bool small = d <= kStackLevels;
  if (!small) {
    largeFlips.resize((std::size_t(1) << d) - 1);
    largeAll.resize(std::size_t(1) << d);
    largeBits.resize(out.size());
  }
  std::uint32_t *const flips = small ? smallFlips.data() : largeFlips.data();
  std::uint32_t *const all = small ? smallAll.data() : largeAll.data();
  const std::span<std::uint32_t> bits(small ? smallBits.data() : largeBits.data(), out.size());
  for (int l = 0; l < d; ++l)
    for (std::uint64_t q = 0; q < (std::uint64_t(1) << l); ++q)
      flips[(std::size_t(1) << l) - 1 + q] =
          tree.digitFlip(q, l) | (l == 0 ? 0u : flips[(std::size_t(1) << (l - 1)) - 1 + (q >> 1)]);
  sobolRun(dim, bits);
  if (d == 0) {  // one point: every digit sits under the empty prefix
    out[0].*coordinate = (bits[0] ^ tree.tailFlips(0, 0)) * 0x1.0p-32;
    return;
  }
  // The tails by prefix, one hash per pair of siblings (2^d < 2n, so fewer
  // hashes than one per point); d < 32 here, so every point has a tail.
  const std::uint32_t *const deepest = flips + (std::size_t(1) << (d - 1)) - 1;
  for (std::uint64_t q = 0; q < (std::uint64_t(1) << (d - 1)); ++q) {
    const auto tails = tree.siblingTailFlips(q, d);
    all[2 * q] = deepest[q] | tails[0];
    all[2 * q + 1] = deepest[q] | tails[1];
  }
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i].*coordinate = (bits[i] ^ all[bits[i] >> (32 - d)]) * 0x1.0p-32;
}

// Sets up to this size use the prefix table (it has about n entries).
constexpr std::size_t kMaxTabulatedOwenSet = std::size_t(1) << 20;

// asSet: the points form one set of out.size() (generateSet); otherwise
// every digit is scrambled separately (generatePoints).
void fill(const SequenceOptions &o, std::uint32_t instance, std::span<Point2> out,
          std::uint32_t firstDim, bool asSet) {
  const auto digits = [&](std::uint32_t dim) {
    if (!asSet) return -1;
    return distinctDigits(out.size(), o.kind == SequenceKind::Halton ? nthPrime(dim) : 2);
  };
  const int d0 = digits(firstDim), d1 = digits(firstDim + 1);
  if (asSet && o.kind == SequenceKind::Sobol && o.scramble == Scramble::Owen &&
      out.size() <= kMaxTabulatedOwenSet) {
    owenSobolCoordinate(dimensionSeed(o.seed, instance, firstDim), firstDim, d0, out, &Point2::x);
    owenSobolCoordinate(dimensionSeed(o.seed, instance, firstDim + 1), firstDim + 1, d1, out,
                        &Point2::y);
    return;
  }
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = {sample(o, i, firstDim, instance, d0), sample(o, i, firstDim + 1, instance, d1)};
}

}  // namespace

double sequenceSample(const SequenceOptions &o, std::uint64_t index, std::uint32_t dim,
                      std::uint32_t instance) {
  return sample(o, index, dim, instance, -1);
}

void generatePoints(const SequenceOptions &o, std::uint32_t instance, std::span<Point2> out,
                    std::uint32_t firstDim) {
  fill(o, instance, out, firstDim, false);
}

void generateSet(const SequenceOptions &o, std::uint32_t instance, std::span<Point2> out,
                 std::uint32_t firstDim) {
  fill(o, instance, out, firstDim, true);
}

PointSet generatePointSet(const SequenceOptions &o, std::size_t n, std::size_t instances) {
  PointSet set;
  set.n = n;
  set.points.resize(n * instances);
  for (std::size_t k = 0; k < instances; ++k)
    generatePoints(o, static_cast<std::uint32_t>(k), set.instance(k));
  setMeta(set, meta::kGenerator, toString(o.kind));
  setMeta(set, meta::kScramble, o.kind == SequenceKind::Random ? "none" : toString(o.scramble));
  setMeta(set, meta::kSeed, std::to_string(o.seed));
  return set;
}

}  // namespace nuld
