// The classic backends: independent random numbers, Owen-scrambled Sobol and
// randomized (Owen-permuted) Halton. Sobol and Halton are padded: every
// (pixel, pair) gets its own independently scrambled copy of the first N
// points of dimensions (0, 1), dealt out in its own random order
// (shufflePoints), so pairs are matched at random, never by index.

#include <stdexcept>

#include "renderer/padding.h"
#include "renderer/sampler_backend.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"

namespace nuld {
namespace {

class IndependentBackend final : public SamplerBackend {
 public:
  explicit IndependentBackend(std::uint64_t seed) : seed_(seed) {}
  std::string name() const override { return "independent"; }
  void primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const override {
    Rng rng(hashCombine(seed_, pixel), pair);
    for (Point2 &p : out) p = {rng.uniform(), rng.uniform()};
  }

 private:
  std::uint64_t seed_;
};

class SequenceBackend final : public SamplerBackend {
 public:
  SequenceBackend(SequenceKind kind, std::uint64_t seed) : kind_(kind), seedKey_(mix64(seed)) {}
  std::string name() const override { return kind_ == SequenceKind::Sobol ? "sobol" : "halton"; }
  void primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const override {
    // One seed per (pixel, pair), by two dependent mixes: hash3's five
    // were most of the cost of a 4-point set.
    const std::uint64_t pixelKey = mix64(seedKey_ + 0x9e3779b97f4a7c15ull * pixel);
    const std::uint64_t seed = mix64(pixelKey ^ (0xd1b54a32d192ed03ull * (pair + 1)));
    generateSet({kind_, Scramble::Owen, seed}, 0, out, 0);
    shufflePoints(out, seed);
  }

 private:
  SequenceKind kind_;
  std::uint64_t seedKey_;
};

}  // namespace

std::unique_ptr<SamplerBackend> makeClassicBackend(const std::string &name, std::uint64_t seed) {
  if (name == "independent" || name == "random") return std::make_unique<IndependentBackend>(seed);
  if (name == "sobol") return std::make_unique<SequenceBackend>(SequenceKind::Sobol, seed);
  if (name == "halton") return std::make_unique<SequenceBackend>(SequenceKind::Halton, seed);
  return nullptr;
}

}  // namespace nuld
