// The classic backends: independent random numbers and the field's
// low-discrepancy samplers (Owen-scrambled Sobol, randomized Halton,
// stratified, pmj02, a shifted rank-1 lattice, zsobol), and -tabulated
// variants: the same points, mapped for every lobe context through the
// tabulated lobe's inverse CDF instead of the material's lobe-selection
// mapping (sobol-tabulated is the classic baseline for BSDF
// sampling; the light domain is inverse-CDF mapped by every backend). The
// set samplers are padded: every (pixel, domain) gets its own independently
// randomized set, dealt out in its own random order (shufflePoints, or the
// order stratified and lattice sets come in), so
// domains are matched at random, never by index. zsobol is the exception by
// design: its domains are decorrelated by its per-domain index
// permutations, and its sets depend on where the pixel is on the screen.
// A 1D domain gets the sampler's own 1D set (sampler/sequences/sets_1d.h):
// van der Corput for sobol and halton, N strata for stratified, the
// lattice's first coordinate; pmj02 and zsobol give their 2D set's first
// coordinate, which is already their 1D construction (pmj02's projections
// are stratified into N; zsobol's first dimension is pbrt's Get1D).

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <vector>

#include "backends/backend_registry.h"
#include "renderer/padding.h"
#include "sampler/sequences/lattice.h"
#include "sampler/sequences/pmj02.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/scrambling.h"
#include "sampler/sequences/sequence.h"
#include "sampler/sequences/sets_1d.h"
#include "sampler/sequences/sobol.h"
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
  bool distributed(const Target &target, std::uint64_t pixel, std::uint32_t domain,
                   std::span<Point2> out) const override {
    if (!mapsPrimaryThrough(target)) return false;
    primary(pixel, domain, out);
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
  void primary(std::uint64_t pixel, std::uint32_t domain, std::span<Point2> out) const override {
    Rng rng(hashCombine(seed_, pixel), domain);
    for (Point2 &p : out) p = {rng.uniform(), rng.uniform()};
  }
  void primary1D(std::uint64_t pixel, std::uint32_t domain, std::span<double> out) const override {
    Rng rng(hashCombine(seed_, pixel), domain);
    for (double &x : out) x = rng.uniform();
  }

 private:
  std::uint64_t seed_;
};

template <SequenceKind kSequence>
void owenSequenceSet(std::uint64_t seed, std::span<Point2> out) {
  generateSet({kSequence, Scramble::Owen, seed}, 0, out, 0);
}

// A set of N points from a seed (each sampler's own randomization), and of N
// numbers.
using SetMaker = void (*)(std::uint64_t seed, std::span<Point2> out);
using SetMaker1D = void (*)(std::uint64_t seed, std::span<double> out);

// A freshly randomized set per (pixel, pair), dealt in a random order.
class SetBackend final : public ClassicBackend {
 public:
  // `ordered`: `make` gives its points in a random order already
  // (stratified, lattice), so they are not shuffled again. `make1D`: the 1D
  // sets (null: the first coordinate of make's). `maxSet`: the largest set
  // `make` makes (0: any).
  SetBackend(BackendKind kind, SetMaker make, SetMaker1D make1D, std::uint64_t seed,
             bool ordered = false, std::size_t maxSet = 0)
      : ClassicBackend(kind),
        make_(make),
        make1D_(make1D),
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
  void primary(std::uint64_t pixel, std::uint32_t domain, std::span<Point2> out) const override {
    const std::uint64_t seed = setSeed(pixel, domain);
    make_(seed, out);
    if (!ordered_) shufflePoints(out, seed);
  }
  void primary1D(std::uint64_t pixel, std::uint32_t domain, std::span<double> out) const override {
    const std::uint64_t seed = setSeed(pixel, domain);
    if (make1D_) return make1D_(seed, out);
    thread_local std::vector<Point2> points;
    points.resize(out.size());
    make_(seed, points);
    if (!ordered_) shufflePoints(points, seed);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = points[i].x;
  }

 private:
  // One seed per (pixel, domain), by two dependent mixes: hash3's five
  // were most of the cost of a 4-point set.
  std::uint64_t setSeed(std::uint64_t pixel, std::uint32_t domain) const {
    const std::uint64_t pixelKey = mix64(seedKey_ + 0x9e3779b97f4a7c15ull * pixel);
    return mix64(pixelKey ^ (0xd1b54a32d192ed03ull * (domain + 1)));
  }

  SetMaker make_;
  SetMaker1D make1D_;
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
  void primary(std::uint64_t pixel, std::uint32_t domain, std::span<Point2> out) const override {
    zsobolSet(seed_, domain, std::uint32_t(pixel % width_), std::uint32_t(pixel / width_), side_,
              out);
  }
  void primary1D(std::uint64_t pixel, std::uint32_t domain, std::span<double> out) const override {
    thread_local std::vector<Point2> points;
    points.resize(out.size());
    primary(pixel, domain, points);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = points[i].x;
  }

 private:
  std::uint64_t seed_;
  std::uint32_t width_ = 1, side_ = 1;  // set by prepare()
};

// sobol-full: every domain of a path at its own dimensions of one Sobol
// sequence (SampleLayout::firstDimension), the pixel's points 0 .. N - 1 in
// index order, each dimension Owen-scrambled by a key of (pixel, dimension):
// the N samples of a pixel are the first N points of one randomized
// sequence in all its dimensions at once. A domain past Sobol's last
// dimension gets a padded set, as sobol's.
class FullSobolBackend final : public ClassicBackend {
 public:
  FullSobolBackend(BackendKind kind, std::uint64_t seed)
      : ClassicBackend(kind),
        seedKey_(mix64(seed)),
        padded_(kind, owenSequenceSet<SequenceKind::Sobol>, vanDerCorputSet, seed) {}
  void prepare(std::size_t spp, const SamplingTargets &targets) override {
    ClassicBackend::prepare(spp, targets);
    note_.clear();
    for (std::uint32_t d = 0; d < targets.domains; ++d)
      if (!inSequence(d)) {
        note_ = "sobol-full: Sobol has " + std::to_string(kSobolMaxDimensions) +
                " dimensions; the domains of bounce " + std::to_string(SampleLayout::bounceOf(d)) +
                " on are padded Owen-Sobol sets";
        break;
      }
  }
  void primary(std::uint64_t pixel, std::uint32_t domain, std::span<Point2> out) const override {
    if (!inSequence(domain)) return padded_.primary(pixel, domain, out);
    const std::uint32_t dim = SampleLayout::firstDimension(domain);
    thread_local std::vector<double> x, y;
    x.resize(out.size()), y.resize(out.size());
    dimension(pixel, dim, x), dimension(pixel, dim + 1, y);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = {x[i], y[i]};
  }
  void primary1D(std::uint64_t pixel, std::uint32_t domain, std::span<double> out) const override {
    if (!inSequence(domain)) return padded_.primary1D(pixel, domain, out);
    dimension(pixel, SampleLayout::firstDimension(domain), out);
  }
  Report report() const override {
    Report r;
    r.note = note_;
    return r;
  }

 private:
  static bool inSequence(std::uint32_t domain) {
    return SampleLayout::firstDimension(domain) + std::uint32_t(SampleLayout::dimensions(domain)) <=
           kSobolMaxDimensions;
  }
  // Points 0 .. N - 1 of Sobol dimension `dim`, scrambled for the pixel.
  void dimension(std::uint64_t pixel, std::uint32_t dim, std::span<double> out) const {
    thread_local std::vector<std::uint32_t> bits;
    bits.resize(out.size());
    sobolRun(dim, bits);
    const int digits = std::max(1, int(std::bit_width(out.size() - 1)));
    const std::uint64_t key = mix64(mix64(seedKey_ + 0x9e3779b97f4a7c15ull * pixel) ^
                                    (0xd1b54a32d192ed03ull * (dim + 1)));
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = owenScramble(bits[i], key, digits) * 0x1.0p-32;
  }

  std::uint64_t seedKey_;
  SetBackend padded_;
  std::string note_;
};

void owenPmj02Set(std::uint64_t seed, std::span<Point2> out) { pmj02Set(seed, out); }
void latticeBakerSet1D(std::uint64_t seed, std::span<double> out) { latticeSet1D(seed, out, true); }
void latticePlainSet1D(std::uint64_t seed, std::span<double> out) { latticeSet1D(seed, out); }

}  // namespace

std::unique_ptr<SamplerBackend> makeClassicBackend(BackendKind kind, std::uint64_t seed) {
  using K = BackendKind;
  switch (kind) {
    case K::Independent:
    case K::IndependentTabulated: return std::make_unique<IndependentBackend>(kind, seed);
    case K::Sobol:
    case K::SobolTabulated:
      return std::make_unique<SetBackend>(kind, owenSequenceSet<SequenceKind::Sobol>,
                                          vanDerCorputSet, seed);
    case K::Halton:
    case K::HaltonTabulated:
      return std::make_unique<SetBackend>(kind, owenSequenceSet<SequenceKind::Halton>,
                                          vanDerCorputSet, seed);
    case K::Stratified:
      return std::make_unique<SetBackend>(kind, stratifiedSet, stratifiedSet1D, seed, true);
    case K::Pmj02:
      return std::make_unique<SetBackend>(kind, owenPmj02Set, nullptr, seed, false, kPmj02MaxSet);
    case K::Lattice:
      return std::make_unique<SetBackend>(kind, latticeSet, latticePlainSet1D, seed, true);
    case K::LatticeBaker:
      return std::make_unique<SetBackend>(kind, latticeBakerSet, latticeBakerSet1D, seed, true);
    case K::ZSobol: return std::make_unique<ZSobolBackend>(kind, seed);
    case K::SobolFull: return std::make_unique<FullSobolBackend>(kind, seed);
    default: throw std::invalid_argument("makeClassicBackend: not a classic backend");
  }
}

}  // namespace nuld
