// The 1D sets of the classic samplers (sampler/sequences/sets_1d.h): one
// number in each of N strata, every number uniform over seeds, and a random
// order per seed.
#include "sampler/sequences/sets_1d.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "tests/common/chi_square.h"

namespace nuld {
namespace {

using Maker = void (*)(std::uint64_t, std::span<double>);
void baker(std::uint64_t seed, std::span<double> out) { latticeSet1D(seed, out, true); }
void lattice(std::uint64_t seed, std::span<double> out) { latticeSet1D(seed, out); }

struct Kind {
  const char *name;
  Maker make;
  bool anyN;  // stratified for every N, not only powers of two
};
const Kind kKinds[] = {{"van der Corput", vanDerCorputSet, false},
                       {"stratified", stratifiedSet1D, true},
                       {"lattice", lattice, true}};

bool oneInEachStratum(const std::vector<double> &v) {
  std::vector<int> count(v.size(), 0);
  for (const double x : v) {
    if (!(x >= 0 && x < 1)) return false;
    ++count[std::size_t(x * double(v.size()))];
  }
  return std::all_of(count.begin(), count.end(), [](int c) { return c == 1; });
}

TEST(Sets1D, EachStratumHoldsOneNumber) {
  for (const Kind &k : kKinds)
    for (const std::size_t n : {1u, 2u, 5u, 16u, 64u, 100u, 1024u}) {
      if (!k.anyN && (n & (n - 1))) continue;
      for (std::uint64_t seed = 0; seed < 20; ++seed) {
        std::vector<double> v(n);
        k.make(seed, v);
        ASSERT_TRUE(oneInEachStratum(v)) << k.name << " N " << n << " seed " << seed;
      }
    }
  // The baker's fold keeps every number in [0, 1) and pairs the strata.
  std::vector<double> v(16);
  baker(3, v);
  for (const double x : v) EXPECT_TRUE(x >= 0 && x < 1) << x;
}

// Number i of a set, over seeds, is uniform (chi-square), and the set's
// order is not its strata's: the first number falls in any stratum.
TEST(Sets1D, NumbersAreUniformOverSeedsInARandomOrder) {
  constexpr int kSeeds = 4000, kBins = 16;
  for (const Kind &k : kKinds) {
    std::vector<double> first(kBins, 0), last(kBins, 0);
    for (int seed = 0; seed < kSeeds; ++seed) {
      std::vector<double> v(8);
      k.make(std::uint64_t(seed) * 7919, v);
      ++first[std::size_t(v.front() * kBins)];
      ++last[std::size_t(v.back() * kBins)];
    }
    const std::vector<double> expected(kBins, double(kSeeds) / kBins);
    EXPECT_GT(test::pooledChiSquare(first, expected).pValue, 1e-4) << k.name;
    EXPECT_GT(test::pooledChiSquare(last, expected).pValue, 1e-4) << k.name;
  }
}

}  // namespace
}  // namespace nuld
