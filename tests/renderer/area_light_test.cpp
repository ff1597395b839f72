// Area lights (renderer/area_light.h) against independent oracles: each
// shape's sampling by a chi-square test against its pdf, the irradiance at
// a Lambertian point against closed forms (pi L sin^2 theta for a sphere,
// Lambert's polygon formula for a rectangle and a triangle) by light,
// cosine and MIS estimators, the stiff cases, and the choice of a light by
// power (renderer/light_power.h).
#include "renderer/area_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "materials/sampling.h"
#include "renderer/light_power.h"
#include "tests/common/chi_square.h"

namespace nuld {
namespace {

constexpr double kPi = std::numbers::pi;

// A unit frame about `axis`.
struct Frame {
  Vec3 t0, t1, n;
  explicit Frame(Vec3 axis) : n(normalize(axis)) {
    const Vec3 helper = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    t0 = normalize(cross(helper, n));
    t1 = cross(n, t0);
  }
  Vec3 toWorld(Vec3 v) const { return v.x * t0 + v.y * t1 + v.z * n; }
  Vec3 toLocal(Vec3 w) const { return {dot(w, t0), dot(w, t1), dot(w, n)}; }
};

// The light's directions from p lie in the cap of half-angle `cap` about
// `axis`; bins are equal in solid angle there: (phi, 1 - cos theta) on a
// W x H grid. Expected counts integrate pdf() over each bin on a 40 x 40
// grid of sub-bins (finer where the light's edge crosses the bin).
test::ChiSquare chiSquareOf(const AreaLight &light, Vec3 p, Vec3 axis, double cap,
                            std::uint32_t seed, int samples = 100000) {
  constexpr int W = 20, H = 20, kSub = 40;
  const Frame frame(axis);
  const double capHeight = 1 - std::cos(cap);  // 1 - cos of the cap's edge
  std::vector<double> observed(W * H, 0), expected(W * H, 0);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0, 1);
  int outside = 0;
  for (int i = 0; i < samples; ++i) {
    const auto s = light.sample(p, {uniform(rng), uniform(rng)});
    if (!s) continue;
    const Vec3 w = frame.toLocal(s->wi);
    const double h = (1 - w.z) / capHeight;
    double phi = std::atan2(w.y, w.x) / (2 * kPi);
    if (phi < 0) phi += 1;
    if (!(h < 1)) {
      ++outside;
      continue;
    }
    observed[std::min(H - 1, int(h * H)) * W + std::min(W - 1, int(phi * W))] += 1;
  }
  EXPECT_EQ(outside, 0) << "samples outside the cap that bounds the light";
  // A bin the light's edge crosses (some sub-bins see it, some do not) is
  // integrated again on a grid 6 times finer: the edge's share of a bin is
  // what a coarse grid gets wrong.
  const auto binMass = [&](int bx, int by, int sub, bool &edge) {
    const double cell = 2 * kPi * capHeight / (double(W) * H * sub * sub);
    double mass = 0;
    int seen = 0;
    for (int sy = 0; sy < sub; ++sy)
      for (int sx = 0; sx < sub; ++sx) {
        const double h = (by + (sy + 0.5) / sub) / H * capHeight;
        const double phi = 2 * kPi * (bx + (sx + 0.5) / sub) / W;
        const double cosTheta = 1 - h, sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
        const Vec3 w =
            frame.toWorld({sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta});
        const double pdf = light.pdf(p, w);
        seen += pdf > 0;
        mass += pdf * cell;
      }
    edge = seen > 0 && seen < sub * sub;
    return mass;
  };
  for (int by = 0; by < H; ++by)
    for (int bx = 0; bx < W; ++bx) {
      bool edge = false;
      double mass = binMass(bx, by, kSub, edge);
      if (edge) mass = binMass(bx, by, 6 * kSub, edge);
      expected[by * W + bx] = mass * samples;
    }
  return test::pooledChiSquare(observed, expected);
}

// The half-angle of the smallest cap about the direction to `centre` that
// holds every `corners` direction, widened so that no sample falls on the
// cap's own edge.
double capOf(Vec3 p, Vec3 centre, std::initializer_list<Vec3> corners) {
  const Vec3 axis = normalize(centre - p);
  double widest = 0;
  for (const Vec3 c : corners)
    widest = std::max(widest, std::acos(std::clamp(dot(axis, normalize(c - p)), -1.0, 1.0)));
  return std::min(kPi, 1.1 * widest);
}

TEST(AreaLight, EveryShapeSamplesItsPdf) {
  const double level = test::sidakLevel(0.01, 7);
  const Rgb L = Rgb::grey(1);
  const AreaLight rect = AreaLight::rectangle({-0.5, 2, -0.25}, {1, 0, 0}, {0, 0, 0.5}, L);
  const AreaLight tri = AreaLight::triangle({0, 2, 0}, {1, 2.5, 0}, {0.2, 2, 1}, L);
  const AreaLight sph = AreaLight::sphere({0.3, 2, -0.2}, 0.4, L);
  const AreaLight tiny = AreaLight::sphere({0, 30, 0}, 0.05, Rgb::grey(3000));
  struct Case {
    std::string name;
    const AreaLight *light;
    Vec3 p, centre;
    std::initializer_list<Vec3> corners;
    double cap = 0;
  };
  const Vec3 rc[] = {{-0.5, 2, -0.25}, {0.5, 2, -0.25}, {-0.5, 2, 0.25}, {0.5, 2, 0.25}};
  std::vector<Case> cases = {
      {"rectangle, overhead", &rect, {0.1, 0, 0.05}, {0, 2, 0}, {rc[0], rc[1], rc[2], rc[3]}},
      // Seen from the side: a thin sliver of solid angle.
      {"rectangle, grazing", &rect, {3, 1.9, 0}, {0, 2, 0}, {rc[0], rc[1], rc[2], rc[3]}},
      // So far that it is sampled by area.
      {"rectangle, far", &rect, {0, -60, 0}, {0, 2, 0}, {rc[0], rc[1], rc[2], rc[3]}},
      {"triangle", &tri, {0.2, 0.5, 0.1}, {0.4, 2.17, 0.33}, {{0, 2, 0}, {1, 2.5, 0}, {0.2, 2, 1}}},
      {"triangle, grazing",
       &tri,
       {-2, 2.02, 0.3},
       {0.4, 2.17, 0.33},
       {{0, 2, 0}, {1, 2.5, 0}, {0.2, 2, 1}}},
  };
  for (Case &c : cases) c.cap = capOf(c.p, c.centre, c.corners);
  cases.push_back({"sphere",
                   &sph,
                   {0, 0, 0},
                   {0.3, 2, -0.2},
                   {},
                   1.1 * std::asin(0.4 / length(Vec3{0.3, 2, -0.2}))});
  cases.push_back(
      {"tiny sphere, far", &tiny, {0, 0, 0}, {0, 30, 0}, {}, 1.1 * std::asin(0.05 / 30)});
  std::uint32_t seed = 1;
  for (const Case &c : cases) {
    const test::ChiSquare x = chiSquareOf(*c.light, c.p, c.centre - c.p, c.cap, seed++);
    EXPECT_GT(x.pValue, level) << c.name << ": chi2 " << x.statistic << " dof " << x.dof << " "
                               << x.note;
  }
}

// Lambert's formula: the irradiance at p (normal n) from a uniform
// polygon of radiance L, E = L/2 sum_i gamma_i n . normalize(r_i x r_i+1).
double polygonIrradiance(Vec3 p, Vec3 n, const std::vector<Vec3> &vertices, double L) {
  double sum = 0;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Vec3 a = normalize(vertices[i] - p),
               b = normalize(vertices[(i + 1) % vertices.size()] - p);
    const double gamma = std::acos(std::clamp(dot(a, b), -1.0, 1.0));
    sum += gamma * dot(n, normalize(cross(a, b)));
  }
  return 0.5 * L * std::abs(sum);
}

struct Estimate {
  double mean = 0, stderr_ = 0;
};
template <class F>
Estimate estimate(int n, std::uint32_t seed, F sampleOnce) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0, 1);
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    const double v =
        sampleOnce(Point2{uniform(rng), uniform(rng)}, Point2{uniform(rng), uniform(rng)});
    EXPECT_TRUE(std::isfinite(v));
    sum += v, sum2 += v * v;
  }
  const double mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1))};
}

// The irradiance at a point facing +y by the light's own sampling, by
// cosine sampling of the hemisphere that hits the light, and by the two
// combined with the power heuristic: each within 3 standard errors of the
// closed form.
void expectIrradiance(const std::string &name, const AreaLight &light, Vec3 p, double exact) {
  const Frame frame({0, 1, 0});
  const double L = light.radiance().r;
  const auto lightOnly = [&](Point2 u, Point2) {
    const auto s = light.sample(p, u);
    if (!s) return 0.0;
    return s->radiance.r * std::max(0.0, s->wi.y) / s->pdf;
  };
  const auto cosineOnly = [&](Point2, Point2 u) {
    const Vec3 wi = frame.toWorld(cosineHemisphere(u));
    return light.pdf(p, wi) > 0 ? L * wi.y / cosineHemispherePdf(wi.y) : 0.0;
  };
  const auto mis = [&](Point2 ul, Point2 ub) {
    double v = 0;
    if (const auto s = light.sample(p, ul); s && s->wi.y > 0)
      v += s->radiance.r * s->wi.y / s->pdf * powerHeuristic(s->pdf, cosineHemispherePdf(s->wi.y));
    const Vec3 wi = frame.toWorld(cosineHemisphere(ub));
    if (const double pl = light.pdf(p, wi); pl > 0)
      v += L * wi.y / cosineHemispherePdf(wi.y) * powerHeuristic(cosineHemispherePdf(wi.y), pl);
    return v;
  };
  std::uint32_t seed = 11;
  for (const auto &[estimator, e] : {std::pair{"light", estimate(200000, seed++, lightOnly)},
                                     std::pair{"cosine", estimate(200000, seed++, cosineOnly)},
                                     std::pair{"mis", estimate(200000, seed++, mis)}}) {
    EXPECT_NEAR(e.mean, exact, 3 * e.stderr_ + 1e-12 * exact)
        << name << ", " << estimator << ": " << e.mean << " +- " << e.stderr_ << " against "
        << exact;
  }
}

TEST(AreaLight, IrradianceMatchesClosedForms) {
  const double L = 2.5;
  // A sphere straight above: E = pi L sin^2 theta_max.
  const Vec3 centre{0, 3, 0};
  const double r = 0.8;
  expectIrradiance("sphere", AreaLight::sphere(centre, r, Rgb::grey(L)), {0, 0, 0},
                   kPi * L * r * r / 9);
  // A rectangle facing down, off to one side.
  const std::vector<Vec3> rect = {
      {0.2, 1.5, -0.4}, {1.2, 1.5, -0.4}, {1.2, 1.5, 0.6}, {0.2, 1.5, 0.6}};
  expectIrradiance(
      "rectangle",
      AreaLight::rectangle(rect[0], rect[1] - rect[0], rect[3] - rect[0], Rgb::grey(L), true),
      {0, 0, 0}, polygonIrradiance({0, 0, 0}, {0, 1, 0}, rect, L));
  const std::vector<Vec3> tri = {{-0.5, 1, 0.3}, {0.7, 1.4, -0.2}, {0.1, 0.9, 1.1}};
  expectIrradiance("triangle", AreaLight::triangle(tri[0], tri[1], tri[2], Rgb::grey(L), true),
                   {0, 0, 0}, polygonIrradiance({0, 0, 0}, {0, 1, 0}, tri, L));
  // A small, far rectangle: sampled by area.
  const std::vector<Vec3> small = {
      {-0.01, 40, -0.01}, {0.01, 40, -0.01}, {0.01, 40, 0.01}, {-0.01, 40, 0.01}};
  const AreaLight far =
      AreaLight::rectangle(small[0], small[1] - small[0], small[3] - small[0], Rgb::grey(L), true);
  const auto s = far.sample({0, 0, 0}, {0.3, 0.7});
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->radiance.r * s->wi.y / s->pdf, polygonIrradiance({0, 0, 0}, {0, 1, 0}, small, L),
              1e-3 * polygonIrradiance({0, 0, 0}, {0, 1, 0}, small, L));
}

// What sample() gives, pdf() gives back, and nothing is NaN or infinite:
// tiny bright lights, grazing and far points, a point on the light's plane
// and behind a one-sided light.
TEST(AreaLight, StiffCasesStayFiniteAndAgreeWithPdf) {
  const AreaLight lights[] = {
      AreaLight::sphere({0, 2, 0}, 0.05, Rgb::grey(3000)),
      AreaLight::sphere({0, 1e4, 0}, 0.05, Rgb::grey(3000)),
      AreaLight::rectangle({-0.5, 2, -0.5}, {1, 0, 0}, {0, 0, 1}, Rgb::grey(3000)),
      AreaLight::triangle({0, 2, 0}, {1e-3, 2, 0}, {0, 2, 1e-3}, Rgb::grey(1e6)),
  };
  const Vec3 points[] = {{0, 0, 0},   {5, 1.999999, 0}, {0, 2, 0.5},
                         {1e3, 0, 0}, {0, 3, 0},        {0, 2.0000001, 0}};
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uniform(0, 1);
  for (const AreaLight &light : lights)
    for (const Vec3 p : points)
      for (int i = 0; i < 200; ++i) {
        const Point2 u{uniform(rng), i == 0 ? 0.0 : i == 1 ? 1 - 1e-16 : uniform(rng)};
        const auto s = light.sample(p, u);
        if (!s) continue;
        ASSERT_TRUE(isFinite(s->wi) && std::isfinite(s->distance) && std::isfinite(s->pdf) &&
                    s->pdf > 0 && std::isfinite(s->radiance.r))
            << "p (" << p.x << ", " << p.y << ", " << p.z << ")";
        const double back = light.pdf(p, s->wi);
        if (back > 0)
          EXPECT_NEAR(back / s->pdf, 1, 1e-6) << "p (" << p.x << ", " << p.y << ", " << p.z << ")";
      }
  // Behind a one-sided rectangle: samples, but no radiance.
  const auto behind = lights[2].sample({0, 3, 0}, {0.5, 0.5});
  ASSERT_TRUE(behind);
  EXPECT_EQ(behind->radiance.r, 0);
  EXPECT_GT(lights[2].sample({0, 1, 0}, {0.5, 0.5})->radiance.r, 0);
}

TEST(LightPowerChooser, ChoosesByPowerWithItsProbabilities) {
  const std::vector<double> powers = {1, 0, 3, 6};
  const LightPowerChooser chooser(powers);
  std::vector<double> observed(4, 0), expected(4, 0);
  const int n = 100000;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uniform(0, 1);
  for (int i = 0; i < n; ++i) {
    const auto c = chooser.choose(uniform(rng));
    observed[c.index] += 1;
    EXPECT_EQ(c.probability, chooser.probability(c.index));
  }
  for (int i = 0; i < 4; ++i) expected[i] = n * powers[i] / 10;
  EXPECT_EQ(observed[1], 0) << "a light of power 0 is never chosen";
  EXPECT_DOUBLE_EQ(chooser.probability(3), 0.6);
  const std::vector<double> kept = {observed[0], observed[2], observed[3]},
                            want = {expected[0], expected[2], expected[3]};
  EXPECT_GT(test::pooledChiSquare(kept, want).pValue, 0.001);
  EXPECT_EQ(chooser.choose(0).index, 0u);
  EXPECT_EQ(chooser.choose(std::nextafter(1.0, 0.0)).index, 3u);
  const std::vector<double> zeros = {0, 0};
  EXPECT_DOUBLE_EQ(LightPowerChooser(zeros).probability(1), 0.5);
  const std::vector<double> bad = {1, -1};
  EXPECT_THROW(LightPowerChooser{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace nuld
