// The classic backends: independent random numbers, Owen-scrambled Sobol and
// randomized (Owen-permuted) Halton, and each -tabulated: the same points,
// mapped for every lobe context through the tabulated lobe's inverse CDF
// instead of the material's lobe-selection mapping (sobol-tabulated is the
// strongest classic baseline for BSDF sampling; the light pair is
// inverse-CDF mapped by every backend). Sobol and Halton are padded: every
// (pixel, pair) gets its own independently scrambled copy of the first N
// points of dimensions (0, 1), dealt out in its own random order
// (shufflePoints), so pairs are matched at random, never by index.

#include <algorithm>
#include <stdexcept>

#include "renderer/backend_registry.h"
#include "renderer/padding.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"

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

class SequenceBackend final : public ClassicBackend {
 public:
  SequenceBackend(BackendKind kind, SequenceKind sequence, std::uint64_t seed)
      : ClassicBackend(kind), sequence_(sequence), seedKey_(mix64(seed)) {}
  void primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const override {
    // One seed per (pixel, pair), by two dependent mixes: hash3's five
    // were most of the cost of a 4-point set.
    const std::uint64_t pixelKey = mix64(seedKey_ + 0x9e3779b97f4a7c15ull * pixel);
    const std::uint64_t seed = mix64(pixelKey ^ (0xd1b54a32d192ed03ull * (pair + 1)));
    generateSet({sequence_, Scramble::Owen, seed}, 0, out, 0);
    shufflePoints(out, seed);
  }

 private:
  SequenceKind sequence_;
  std::uint64_t seedKey_;
};

}  // namespace

std::unique_ptr<SamplerBackend> makeClassicBackend(BackendKind kind, std::uint64_t seed) {
  using K = BackendKind;
  switch (kind) {
    case K::Independent:
    case K::IndependentTabulated: return std::make_unique<IndependentBackend>(kind, seed);
    case K::Sobol:
    case K::SobolTabulated:
      return std::make_unique<SequenceBackend>(kind, SequenceKind::Sobol, seed);
    case K::Halton:
    case K::HaltonTabulated:
      return std::make_unique<SequenceBackend>(kind, SequenceKind::Halton, seed);
    default: throw std::invalid_argument("makeClassicBackend: not a classic backend");
  }
}

}  // namespace nuld
