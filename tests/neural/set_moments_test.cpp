// The low-order moments of set_moments.h: the target means against closed
// forms, the gradients against finite differences, and a large
// Owen-scrambled set's errors near zero.

#include "sampler/neural/set_moments.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sampler/sequences/sequence.h"
#include "sampler/targets/target_spec.h"

namespace nuld {
namespace {

TEST(SetMoments, TargetMeansEqualClosedForms) {
  // The uniform quarter disc of radius 1: E[x] = E[y] = 4 / (3 pi), E[x^2] =
  // E[y^2] = 1/4, E[x y] = 1 / (2 pi); the moments are about (1/2, 1/2).
  const double m = 4 / (3 * std::numbers::pi);
  const std::vector<double> disc = targetMoments(*makeTarget("quarterdisc"), Domain::Square);
  ASSERT_EQ(disc.size(), 5u);
  EXPECT_NEAR(disc[0], m - 0.5, 2e-5);
  EXPECT_NEAR(disc[1], m - 0.5, 2e-5);
  EXPECT_NEAR(disc[2], 0.25 - m + 0.25, 2e-5);
  EXPECT_NEAR(disc[3], 1 / (2 * std::numbers::pi) - m + 0.25, 2e-5);
  EXPECT_NEAR(disc[4], 0.25 - m + 0.25, 2e-5);
  // Uniform in the equal-area parameterization is uniform on the sphere:
  // E[w] = 0, E[w_a w_b] = delta_ab / 3.
  const std::vector<double> sphere = targetMoments(*makeTarget("uniform"), Domain::Sphere);
  ASSERT_EQ(sphere.size(), 9u);
  const double expected[9] = {0, 0, 0, 1.0 / 3, 0, 0, 1.0 / 3, 0, 1.0 / 3};
  for (int a = 0; a < 9; ++a) EXPECT_NEAR(sphere[std::size_t(a)], expected[a], 1e-4) << a;
}

TEST(SetMoments, GradientsMatchFiniteDifferences) {
  for (const Domain domain : {Domain::Square, Domain::Sphere})
    for (const Point2 x : {Point2{0.3, 0.7}, Point2{0.91, 0.05}, Point2{0.5, 0.5}}) {
      const MomentValues m = momentsAt(x, domain);
      const double h = 1e-6;
      for (int a = 0; a < m.count; ++a) {
        const double dx = (momentsAt({x.x + h, x.y}, domain).value[a] -
                           momentsAt({x.x - h, x.y}, domain).value[a]) / (2 * h);
        const double dy = (momentsAt({x.x, x.y + h}, domain).value[a] -
                           momentsAt({x.x, x.y - h}, domain).value[a]) / (2 * h);
        EXPECT_NEAR(m.gradient[a].x, dx, 1e-6) << a;
        EXPECT_NEAR(m.gradient[a].y, dy, 1e-6) << a;
      }
    }
}

TEST(SetMoments, ALargeOwenSetThroughTheInverseCdfHasTheTargetsMoments) {
  const auto target = makeTarget("quarterdisc");
  std::vector<Point2> u(1 << 14);
  generateSet({SequenceKind::Sobol, Scramble::Owen, 3}, 0, u);
  for (Point2 &p : u) p = target->invert(p).x;
  for (const double e : momentErrors(u, Domain::Square, targetMoments(*target, Domain::Square)))
    EXPECT_LT(std::abs(e), 2e-4);
}

}  // namespace
}  // namespace nuld
