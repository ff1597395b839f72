// What a word's set plans ask of a scene: the lobe bins camera rays' first
// hits take (lobeTableVisits), checked on a sphere whose view angles are
// known in closed form.

#include "backends/set_plans.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "materials/disney.h"
#include "tests/renderer/lobe_cases.h"
#include "tests/renderer/test_scenes.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;

using test::everyBin;
using test::material;

// The bins first hits take, by tracing camera rays: a sphere seen from far
// away (nearly orthographic) shows view angle theta at radius sin(theta) of
// its disc, so the share of its hits in the bin [a, b] is sin^2 b - sin^2 a.
// Every table the rays take is a serving table; nothing else is counted.
TEST(SetPlans, CameraRaysVisitTheBinsTheirViewAnglesFallIn) {
  CameraSettings camera;
  camera.eye = {0, 0, 40};
  camera.target = {0, 0, 0};
  camera.fovDegrees = 2 * std::asin(1.0 / 40) * 180 / kPi;
  const Scene scene =
      test::sceneWith({test::unitSphere(96, 192)}, {material(0.5, 0, 0)}, std::nullopt, camera);
  const LobeTables tables(scene.materials, everyBin(0.05));
  const LobeVisits visits = lobeTableVisits(scene, tables, 160, 160, 2);
  EXPECT_EQ(visits.total, 160u * 160 * 4);
  const auto targets = tables.targets();
  ASSERT_EQ(targets.size(), 9u);
  std::size_t hits = 0;
  for (const auto &[table, n] : visits.rays) {
    EXPECT_NE(std::find(targets.begin(), targets.end(), table), targets.end());
    hits += n;
  }
  // The disc fills the square frame's inscribed circle: pi / 4 of the rays.
  EXPECT_NEAR(double(hits) / double(visits.total), kPi / 4, 0.01);
  for (int b = 0; b < 9; ++b) {
    const double a = b * 10 * kPi / 180, c = (b + 1) * 10 * kPi / 180;
    const double expected = std::pow(std::sin(c), 2) - std::pow(std::sin(a), 2);
    const auto it = visits.rays.find(targets[std::size_t(b)]);
    const double share = it == visits.rays.end() ? 0 : double(it->second) / double(hits);
    EXPECT_NEAR(share, expected, 0.01) << "bin " << b;
  }
}

}  // namespace
}  // namespace nuld
