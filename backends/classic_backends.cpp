// The classic backends: independent random numbers and the field's
// low-discrepancy samplers (Owen-scrambled Sobol, randomized Halton,
// stratified, pmj02, a shifted rank-1 lattice, zsobol), and -tabulated
// variants: the same points, mapped for every lobe context through the
// tabulated lobe's inverse CDF instead of the material's lobe-selection
// mapping (sobol-tabulated is the classic baseline for BSDF
// sampling; the light pair is inverse-CDF mapped by every backend). The set
// samplers are padded: every (pixel, pair) gets its own independently
// randomized set, dealt out in its own random order (shufflePoints, or the
// order stratified and lattice sets come in), so
// pairs are matched at random, never by index. zsobol is the exception by
// design: its pairs are decorrelated by its per-pair index permutations,
// and its sets depend on where the pixel is on the screen.

#include <algorithm>
#include <bit>
#include <stdexcept>

#include "backends/backend_registry.h"
#include "renderer/padding.h"
#include "sampler/sequences/lattice.h"
#include "sampler/sequences/pmj02.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"
#include "sampler/sequences/stratified.h"
#include "sampler/sequences/zsobol.h"

namespace nuld {
namespace {

// What every classic backend shares: its word and, for a -tabulated one,
// the lobes whose BSDF samples go through their table's inverse CDF.
class ClassicBackend : public SamplerBackend {
 public:
  // A -tabulated kind (its entry's `lobes`) maps lobe contexts through their tables.
  explicit ClassicBackend(BackendKind kind) : kind_(kind), tabulated_(backendEntry(kind).lobes) {}
  std::string name() const override { return backendEntry(kind_).name; }
  bool samplesLobes() const override { return tabulated_; }
  void prepare(std::size_t, const SamplingTargets &targets) override {
    lobes_ = tabulated_ ? targets.lobes : std::vector<const Target *>{};
  }
  // The pair's primary points through the lobe's inverse CDF: for a pixel
  // whose samples all sample one table, exactly the sequence through it.
  bool distributed(const Target &target, std::uint64_t pixel, std::uint32_t pair,
                   std::span<Point2> out) const override {
    if (!mapsPrimaryThrough(target)) return false;
    primary(pixel, pair, out);
    for (Point2 &p : out) p = target.invert(p).x;
    return true;
  }
  bool mapsPrimaryThrough(const Target &target) const override {
    return std::find(lobes_.begin(), lobes_.end(), &target) != lobes_.end();
  }

 private:
  BackendKind kind_;
  bool tabulated_;
  std::vector<const Target *> lobes_;  // set by prepare()
};

class IndependentBackend final : public ClassicBackend {
 public:
  IndependentBackend(BackendKind kind, std::uint64_t seed) : ClassicBackend(kind), seed_(seed) {}
  void primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const override {
    Rng rng(hashCombine(seed_, pixel), pair);
    for (Point2 &p : out) p = {rng.uniform(), rng.uniform()};
  }

 private:
  std::uint64_t seed_;
};

// A set of N points from a seed (each sampler's own randomization).
using SetMaker = void (*)(std::uint64_t seed, std::span<Point2> out);

// A freshly randomized set per (pixel, pair), dealt in a random order.
class SetBackend final : public ClassicBackend {
 public:
  // `ordered`: `make` gives its points in a random order already
  // (stratified, lattice), so they are not shuffled again. `maxSet`: the
  // largest set `make` makes (0: any).
  SetBackend(BackendKind kind, SetMaker make, std::uint64_t seed, bool ordered = false,
             std::size_t maxSet = 0)
      : ClassicBackend(kind),
        make_(make),
        seedKey_(mix64(seed)),
        ordered_(ordered),
        maxSet_(maxSet) {}
  void prepare(std::size_t spp, const SamplingTargets &targets) override {
    if (maxSet_ && spp > maxSet_)
      throw BackendRefusal(name() + ": makes sets of at most " + std::to_string(maxSet_) +
                           " points, but the render asks for " + std::to_string(spp) +
                           " samples per pixel");
    ClassicBackend::prepare(spp, targets);
  }
  void primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const override {
    // One seed per (pixel, pair), by two dependent mixes: hash3's five
    // were most of the cost of a 4-point set.
    const std::uint64_t pixelKey = mix64(seedKey_ + 0x9e3779b97f4a7c15ull * pixel);
    const std::uint64_t seed = mix64(pixelKey ^ (0xd1b54a32d192ed03ull * (pair + 1)));
    make_(seed, out);
    if (!ordered_) shufflePoints(out, seed);
  }

 private:
  SetMaker make_;
  std::uint64_t seedKey_;
  bool ordered_;
  std::size_t maxSet_;
};

// zsobol: pixel (x, y)'s block of the image's one sequence.
class ZSobolBackend final : public ClassicBackend {
 public:
  ZSobolBackend(BackendKind kind, std::uint64_t seed) : ClassicBackend(kind), seed_(seed) {}
  void prepare(std::size_t spp, const SamplingTargets &targets) override {
    ClassicBackend::prepare(spp, targets);
    if (targets.width == 0 || targets.height == 0)
      throw BackendRefusal("zsobol: orders samples over an image; it serves renders only");
    width_ = targets.width;
    side_ = std::bit_ceil(std::max(targets.width, targets.height));
    const int bits = 2 * std::countr_zero(side_) + int(std::bit_width(spp - 1));
    if (bits > 32)
      throw BackendRefusal("zsobol: " + std::to_string(targets.width) + "x" +
                           std::to_string(targets.height) + " pixels at " + std::to_string(spp) +
                           " spp need " + std::to_string(bits) +
                           " bits of Sobol index, more than its 32 (fewer pixels or spp)");
  }
  void primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const override {
    zsobolSet(seed_, pair, std::uint32_t(pixel % width_), std::uint32_t(pixel / width_), side_,
              out);
  }

 private:
  std::uint64_t seed_;
  std::uint32_t width_ = 1, side_ = 1;  // set by prepare()
};

template <SequenceKind kSequence>
void owenSequenceSet(std::uint64_t seed, std::span<Point2> out) {
  generateSet({kSequence, Scramble::Owen, seed}, 0, out, 0);
}

void owenPmj02Set(std::uint64_t seed, std::span<Point2> out) { pmj02Set(seed, out); }

}  // namespace

std::unique_ptr<SamplerBackend> makeClassicBackend(BackendKind kind, std::uint64_t seed) {
  using K = BackendKind;
  switch (kind) {
    case K::Independent:
    case K::IndependentTabulated: return std::make_unique<IndependentBackend>(kind, seed);
    case K::Sobol:
    case K::SobolTabulated:
      return std::make_unique<SetBackend>(kind, owenSequenceSet<SequenceKind::Sobol>, seed);
    case K::Halton:
    case K::HaltonTabulated:
      return std::make_unique<SetBackend>(kind, owenSequenceSet<SequenceKind::Halton>, seed);
    case K::Stratified: return std::make_unique<SetBackend>(kind, stratifiedSet, seed, true);
    case K::Pmj02:
      return std::make_unique<SetBackend>(kind, owenPmj02Set, seed, false, kPmj02MaxSet);
    case K::Lattice: return std::make_unique<SetBackend>(kind, latticeSet, seed, true);
    case K::LatticeBaker: return std::make_unique<SetBackend>(kind, latticeBakerSet, seed, true);
    case K::ZSobol: return std::make_unique<ZSobolBackend>(kind, seed);
    default: throw std::invalid_argument("makeClassicBackend: not a classic backend");
  }
}

}  // namespace nuld
