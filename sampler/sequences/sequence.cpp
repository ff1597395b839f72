#include "sampler/sequences/sequence.h"

#include <array>
#include <stdexcept>
#include <vector>

#include "sampler/io/pointset_metadata.h"
#include "sampler/sequences/lattice.h"
#include "sampler/sequences/owen_set.h"
#include "sampler/sequences/pmj02.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/scrambling.h"
#include "sampler/sequences/sobol.h"
#include "sampler/sequences/stratified.h"

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

Scramble defaultScramble(SequenceKind kind) {
  switch (kind) {
    case SequenceKind::Lattice: return Scramble::CranleyPatterson;
    case SequenceKind::Stratified:
    case SequenceKind::Random: return Scramble::None;
    default: return Scramble::Owen;
  }
}

void checkScramble(const SequenceOptions &o) {
  const auto refuse = [&](const std::string &why) {
    throw std::invalid_argument("scrambling '" + std::string(toString(o.scramble)) +
                                "' does not apply to sequence '" + std::string(toString(o.kind)) +
                                "'" + why);
  };
  const Scramble s = o.scramble;
  if (o.kind == SequenceKind::Stratified && s != Scramble::None)
    refuse(": its jitter, one uniform point per cell, is its randomization (expected none)");
  if (o.kind == SequenceKind::Pmj02 && s == Scramble::CranleyPatterson)
    refuse(": a toroidal shift would break its (0,2) nets (expected owen, shift or none)");
  if (o.kind == SequenceKind::Lattice && s == Scramble::Owen)
    refuse(" (expected cp or shift, its random toroidal shift, baker, or none)");
  if (o.kind != SequenceKind::Lattice && s == Scramble::Baker)
    refuse(": the baker's transform folds a shifted lattice (expected lattice)");
}

bool randomizesInstances(const SequenceOptions &o) {
  return o.kind == SequenceKind::Random || o.kind == SequenceKind::Stratified ||
         o.scramble != Scramble::None;
}

namespace {

// The digit randomization a scrambling names (cp is none: it is applied
// after the digits).
DigitRandomization digitRandomization(Scramble s) {
  return s == Scramble::Owen    ? DigitRandomization::Owen
         : s == Scramble::Shift ? DigitRandomization::Shift
                                : DigitRandomization::None;
}

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
      const double x = radicalInverse(index, nthPrime(dim), digitRandomization(o.scramble), seed,
                                      distinct < 0 ? 64 : distinct);
      return o.scramble == Scramble::CranleyPatterson ? cranleyPatterson(x, seed) : x;
    }
    case SequenceKind::Pmj02:
      return pmj02Sample(dimensionSeed(o.seed, instance, dim & ~1u), index, int(dim & 1),
                         digitRandomization(o.scramble));
    case SequenceKind::Stratified:
    case SequenceKind::Lattice:
      throw std::invalid_argument("sequence '" + std::string(toString(o.kind)) +
                                  "' is a set of N points, not a sequence: its points depend on "
                                  "N, so it has no point by index (make whole sets)");
  }
  return 0;
}

// One coordinate of an Owen-scrambled Sobol set of n = out.size() points,
// the same values as sample() with `distinct` = d = ceil(log2 n) digits, with
// one hash per shared prefix instead of per digit (owen_set.h). The
// renderer's sobol backend scrambles every pixel and pair afresh with it.
void owenSobolCoordinate(std::uint64_t seed, std::uint32_t dim, int d, std::span<Point2> out,
                         double Point2::*coordinate) {
  // The points' Sobol integers: on the stack for the renderer's small sets.
  std::array<std::uint32_t, 256> small;
  thread_local std::vector<std::uint32_t> large;
  if (out.size() > small.size()) large.resize(out.size());
  const std::span<std::uint32_t> bits(out.size() > small.size() ? large.data() : small.data(),
                                      out.size());
  sobolRun(dim, bits);
  owenScrambleSet(seed, d, bits, out, coordinate);
}

// Sets up to this size use the prefix table (it has about n entries).
constexpr std::size_t kMaxTabulatedOwenSet = std::size_t(1) << 20;

// asSet: the points form one set of out.size() (generateSet); otherwise
// every digit is scrambled separately (generatePoints).
void fill(const SequenceOptions &o, std::uint32_t instance, std::span<Point2> out,
          std::uint32_t firstDim, bool asSet) {
  checkScramble(o);
  const std::uint64_t setSeed = dimensionSeed(o.seed, instance, firstDim);
  switch (o.kind) {
    case SequenceKind::Stratified: return stratifiedSet(setSeed, out);
    case SequenceKind::Lattice:
      if (o.scramble == Scramble::None) return rank1Lattice(out);
      return o.scramble == Scramble::Baker ? latticeBakerSet(setSeed, out)
                                           : latticeSet(setSeed, out);
    case SequenceKind::Pmj02:
      checkPmj02Count(out.size());
      // A pair's set: its two coordinates share one base sequence.
      if (asSet && firstDim % 2 == 0) return pmj02Set(setSeed, out, digitRandomization(o.scramble));
      break;
    default: break;
  }
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
  checkScramble(o);
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
