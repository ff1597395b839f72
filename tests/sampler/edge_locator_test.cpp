#include "sampler/targets/edge_locator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sampler/sequences/rng.h"

namespace nuld {
namespace {

// Oracle: the last cell whose lower edge is <= t, clamped to the cells.
int bruteForceCell(const std::vector<double> &e, double t) {
  const int cells = int(e.size()) - 1;
  const int c = int(std::upper_bound(e.begin(), e.end(), t) - e.begin()) - 1;
  return std::clamp(c, 0, cells - 1);
}

TEST(EdgeLocator, MatchesBinarySearchOnUnevenAndRepeatedEdges) {
  Rng rng(5);
  // Equal-area rows (thin near the poles), random edges and repeated edges.
  std::vector<std::vector<double>> cases;
  std::vector<double> poles(513);
  for (int j = 0; j <= 512; ++j) poles[j] = 0.5 * (1 - std::cos(M_PI * j / 512));
  poles.back() = 1;
  cases.push_back(poles);
  std::vector<double> random = {0, 1};
  for (int i = 0; i < 40; ++i) random.push_back(rng.uniform());
  std::sort(random.begin(), random.end());
  cases.push_back(random);
  cases.push_back({0, 0.25, 0.25, 0.25, 0.5, 1, 1});
  cases.push_back({-0.5, 0.1, 2.0});
  for (const auto &e : cases) {
    const EdgeLocator loc(e);
    for (int k = 0; k < 20000; ++k) {
      const double t = e.front() - 0.1 + (e.back() - e.front() + 0.2) * rng.uniform();
      ASSERT_EQ(loc.cell(e, t), bruteForceCell(e, t)) << t;
    }
    for (double t : e) ASSERT_EQ(loc.cell(e, t), bruteForceCell(e, t)) << "edge " << t;
    EXPECT_EQ(loc.cell(e, -INFINITY), 0);
    EXPECT_EQ(loc.cell(e, INFINITY), int(e.size()) - 2);
  }
}

}  // namespace
}  // namespace nuld
