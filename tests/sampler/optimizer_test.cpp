// The direct optimizer: it improves discrepancy, stays in the domain, never
// produces NaN, and resumes bit-identically from a checkpoint.
#include "sampler/optimize/optimizer.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "sampler/io/pointset_metadata.h"
#include "sampler/metrics/discrepancy.h"
#include "sampler/metrics/nonuniform_l2.h"
#include "sampler/optimize/schedule.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/grid_target.h"

namespace nuld {
namespace {

OptimizerSettings small(std::size_t n, int epochs) {
  OptimizerSettings s = presetSettings("uniform", n);
  s.epochs = epochs;
  s.boxes = 2048;
  s.instances = 2;
  s.seed = 3;
  return s;
}

// Oracle: the closed form of docs/architecture.md, "Metrics", and its gradient, written out
// independently of the library's CDF-field implementation.
double closedFormL2asdSquared(std::span<const Point2> p, std::span<Point2> grad = {}) {
  const double N = double(p.size());
  auto G = [](double t) { return (1 + 2 * t - 2 * t * t) / 4; };
  auto dG = [](double t) { return (1 - 2 * t) / 2; };
  double single = 0, pair = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    single += G(p[i].x) * G(p[i].y);
    double gx = 0, gy = 0;
    for (std::size_t j = 0; j < p.size(); ++j) {
      const double dx = p[i].x - p[j].x, dy = p[i].y - p[j].y;
      pair += (1 - std::abs(dx)) * (1 - std::abs(dy));
      gx -= (dx > 0 ? 1.0 : dx < 0 ? -1.0 : 0.0) * (1 - std::abs(dy));
      gy -= (dy > 0 ? 1.0 : dy < 0 ? -1.0 : 0.0) * (1 - std::abs(dx));
    }
    if (!grad.empty())
      grad[i] = {-2 * dG(p[i].x) * G(p[i].y) / N + gx / (2 * N * N),
                 -2 * G(p[i].x) * dG(p[i].y) / N + gy / (2 * N * N)};
  }
  return 1.0 / 9.0 - 2 * single / N + pair / (4 * N * N);
}

// Every gradient component against a central difference of step h, within
// rel * |gradient| + abs.
void expectCentralDifferences(const NonuniformL2asd &objective, std::vector<Point2> pts,
                              const std::vector<Point2> &grad, double h, double rel, double abs) {
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (int k = 0; k < 2; ++k) {
      const double x0 = pts[i][k];
      pts[i][k] = x0 + h;
      const double up = objective.squared(pts);
      pts[i][k] = x0 - h;
      const double down = objective.squared(pts);
      pts[i][k] = x0;
      EXPECT_NEAR(grad[i][k], (up - down) / (2 * h), rel * std::abs(grad[i][k]) + abs)
          << "point " << i << " axis " << k;
    }
}

double meanL2asd(const PointSet &set) {
  double sum = 0;
  for (std::size_t k = 0; k < set.instances(); ++k) sum += l2asd(set.instance(k));
  return sum / double(set.instances());
}

TEST(Schedule, EndpointsAndShape) {
  EXPECT_DOUBLE_EQ(logLinear(1e-3, 1e-7, 0, 100), 1e-3);
  EXPECT_DOUBLE_EQ(logLinear(1e-3, 1e-7, 99, 100), 1e-7);
  EXPECT_NEAR(logLinear(1e-3, 1e-7, 33, 67), 1e-5, 1e-12);  // geometric midpoint
  EXPECT_DOUBLE_EQ(linearRamp(20, 2000, 0.5, 0, 1000), 20);
  EXPECT_DOUBLE_EQ(linearRamp(20, 2000, 0.5, 499, 1000), 2000);
  EXPECT_DOUBLE_EQ(linearRamp(20, 2000, 0.5, 900, 1000), 2000);
}

TEST(ExactL2asdObjective, ValueAndGradientMatchOracles) {
  const PointSet set = generatePointSet({SequenceKind::Random, Scramble::None, 4}, 23, 1);
  std::vector<Point2> pts = set.points, grad(pts.size());
  const UniformTarget uniform;
  const NonuniformL2asd objective(uniform, 1);  // what the optimizer uses
  const double value = objective.squared(pts, grad);
  EXPECT_NEAR(value, std::pow(l2asd(pts), 2), 1e-15);
  // The objective is piecewise quadratic, so central differences are exact
  // up to rounding (about 1e-16 / h) unless a kink |x_i - x_j| lies within h.
  expectCentralDifferences(objective, pts, grad, 1e-5, 1e-7, 1e-10);
}

TEST(DirectOptimizer, LowersL2asdFromItsSobolStart) {
  const UniformTarget uniform;
  for (Objective obj : {Objective::SoftBoxes, Objective::ExactL2asd}) {
    OptimizerSettings s = small(64, 300);
    s.objective = obj;
    const DirectOptimizer opt(uniform, s);
    OptimizerState state = opt.initialState();
    const double before = meanL2asd(opt.points(state));
    opt.run(state, s.epochs);
    const double after = meanL2asd(opt.points(state));
    EXPECT_LT(after, 0.9 * before) << toString(obj);
  }
}

TEST(DirectOptimizer, ExactObjectiveOnAGridTargetImprovesDiscrepancy) {
  std::vector<double> density(64, 1.0);
  for (int i = 0; i < 64; i += 3) density[i] = 5.0;
  density[9] = 0;
  const GridTarget grid(GridTarget::uniformEdges(8), GridTarget::uniformEdges(8), density, "grid",
                        Domain::Square, "test");
  OptimizerSettings s = small(64, 200);
  s.objective = Objective::ExactL2asd;
  s.lrStart = 1e-3;
  const DirectOptimizer opt(grid, s);
  OptimizerState state = opt.initialState();
  const double before = nonuniformL2asd(opt.points(state).instance(0), grid);
  opt.run(state, s.epochs);
  EXPECT_LT(nonuniformL2asd(opt.points(state).instance(0), grid), 0.9 * before);
}

TEST(DirectOptimizer, MappedNonUniformImprovesDiscrepancy) {
  const QuarterDiscTarget disc;
  OptimizerSettings s = presetSettings("nonuniform", 64);
  s.epochs = 300;
  s.boxes = 2048;
  s.lrStart = 1e-3;
  const DirectOptimizer opt(disc, s);
  OptimizerState state = opt.initialState();
  const double before = nonuniformL2asd(opt.points(state).instance(0), disc);
  opt.run(state, s.epochs);
  const PointSet out = opt.points(state);
  EXPECT_LT(nonuniformL2asd(out.instance(0), disc), 0.9 * before);
  for (const Point2 &p : out.points) EXPECT_GT(disc.pdf(p), 0.0);
}

// Every mapping keeps points in the unit square, on the square and the sphere.
TEST(DirectOptimizer, PointsStayInTheDomain) {
  std::vector<double> density(16, 1.0);
  density[5] = 0;
  const GridTarget sphere(GridTarget::uniformEdges(4), GridTarget::uniformEdges(4), density,
                          "test-sphere", Domain::Sphere, "test");
  const StepTarget step(0.5, 0.0, 1.0);  // empty left half
  for (const Target *t : {static_cast<const Target *>(&sphere), static_cast<const Target *>(&step)})
    for (Mapping m : {Mapping::Mapped, Mapping::Clamp, Mapping::Toroidal}) {
      OptimizerSettings s = small(50, 60);
      s.mapping = m;
      s.lrStart = 0.05;  // large steps push points across the boundary
      const DirectOptimizer opt(*t, s);
      OptimizerState state = opt.initialState();
      opt.run(state, s.epochs);
      for (const Point2 &p : opt.points(state).points) {
        ASSERT_TRUE(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1)
            << t->spec() << " " << toString(m) << " (" << p.x << ", " << p.y << ")";
      }
    }
}

TEST(DirectOptimizer, NoNaNUnderExtremeSettings) {
  const StepTarget step(0.5, 0.0, 1.0);
  const QuarterDiscTarget disc;
  for (const Target *t : {static_cast<const Target *>(&step), static_cast<const Target *>(&disc)})
    for (std::size_t n : {1u, 7u}) {
      OptimizerSettings s = small(n, 40);
      s.alphaStart = s.alphaEnd = 1e4;
      s.lrStart = s.lrEnd = 0.1;
      const DirectOptimizer opt(*t, s);
      OptimizerState state = opt.initialState();
      opt.run(state, s.epochs, [&](const EpochReport &r) { ASSERT_TRUE(std::isfinite(r.loss)); });
      for (const Point2 &p : opt.points(state).points) ASSERT_TRUE(isFinite(p));
    }
}

TEST(DirectOptimizer, ResumeFromCheckpointIsBitIdentical) {
  const BilinearTarget target(1, 2, 0.5, 3);
  OptimizerSettings s = small(100, 50);
  s.mcSamples = 4096;  // the Monte Carlo path must resume exactly too
  const DirectOptimizer opt(target, s);
  OptimizerState full = opt.initialState();
  opt.run(full, s.epochs);

  const auto path = std::filesystem::temp_directory_path() /
                    ("nuld_ckpt_test_" + std::to_string(::getpid()) + ".ckpt");
  OptimizerState part = opt.initialState();
  opt.run(part, 23);
  saveCheckpoint(path.string(), opt, target.spec(), part);
  OptimizerState resumed = loadCheckpoint(path.string(), opt, target.spec());
  EXPECT_EQ(resumed.epoch, 23);
  opt.run(resumed, s.epochs);
  EXPECT_EQ(resumed.params, full.params);
  EXPECT_EQ(resumed.m, full.m);
  EXPECT_EQ(resumed.v, full.v);

  // Other settings: a clear refusal.
  OptimizerSettings other = s;
  other.seed = 4;
  const DirectOptimizer opt2(target, other);
  try {
    loadCheckpoint(path.string(), opt2, target.spec());
    FAIL() << "expected an error";
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("other settings"), std::string::npos);
  }
  std::filesystem::remove(path);
}

// A run split into parts (one per MPI rank: firstInstance) makes the same
// sets as one run, on the Monte Carlo and the mapped paths alike.
TEST(DirectOptimizer, InstancesOptimizedInPartsMatchOneRun) {
  const BilinearTarget target(1, 2, 0.5, 3);
  OptimizerSettings s = small(40, 12);
  s.instances = 5;
  s.mcSamples = 1024;
  const DirectOptimizer whole(target, s);
  OptimizerState all = whole.initialState();
  whole.run(all, s.epochs);
  std::vector<Point2> joined;
  for (const auto &[first, count] : {std::pair<std::size_t, std::size_t>{0, 2}, {2, 1}, {3, 2}}) {
    OptimizerSettings part = s;
    part.firstInstance = first;
    part.instances = count;
    const DirectOptimizer opt(target, part);
    OptimizerState state = opt.initialState();
    opt.run(state, s.epochs);
    joined.insert(joined.end(), state.params.begin(), state.params.end());
  }
  EXPECT_EQ(joined, all.params);
  // The bank term couples the instances: no parts.
  OptimizerSettings bank = small(10, 10);
  bank.objective = Objective::ExactL2asd;
  bank.unionWeight = 1;
  bank.firstInstance = 2;
  EXPECT_THROW(DirectOptimizer(UniformTarget{}, bank), std::invalid_argument);
}

// The bank term: instances optimized for the L2asd of their groups' unions
// as well as their own make a bank whose union is more even than that of
// instances optimized apart, at a small cost to each set.
TEST(DirectOptimizer, UnionTermKeepsABanksUnionEven) {
  const UniformTarget u;
  OptimizerSettings s = small(8, 300);
  s.objective = Objective::ExactL2asd;
  s.instances = 16;
  s.lrStart = 1e-2;
  auto optimized = [&](double weight) {
    OptimizerSettings w = s;
    w.unionWeight = weight;
    w.unionGroup = 16;
    const DirectOptimizer opt(u, w);
    OptimizerState state = opt.initialState();
    opt.run(state, w.epochs, [](const EpochReport &r) {
      ASSERT_TRUE(std::isfinite(r.loss) && std::isfinite(r.unionLoss));
    });
    return opt.points(state);
  };
  const PointSet apart = optimized(0), bank = optimized(4);
  const double unionApart = l2asd(apart.points), unionBank = l2asd(bank.points);
  EXPECT_LT(unionBank, 0.8 * unionApart) << "union L2asd " << unionBank << " vs " << unionApart;
  EXPECT_LT(meanL2asd(bank), 1.5 * meanL2asd(apart));
  // Points still in the square, and the settings say the term is on.
  for (const Point2 &p : bank.points) ASSERT_TRUE(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1);
  EXPECT_NE(bank.metadata.at("settings").find("union=4/16"), std::string::npos);
  EXPECT_EQ(apart.metadata.at("settings").find("union="), std::string::npos);
}

// The regrouping is keyed by seed and epoch, so a resumed bank ends the same.
TEST(DirectOptimizer, UnionTermResumesBitIdentical) {
  std::vector<double> density(64, 1.0);
  for (int i = 0; i < 64; i += 5) density[i] = 9.0;
  const GridTarget grid(GridTarget::uniformEdges(8), GridTarget::uniformEdges(8), density, "grid",
                        Domain::Square, "test");
  OptimizerSettings s = small(12, 40);
  s.objective = Objective::ExactL2asd;
  s.instances = 7;  // groups of 3, 3 and a lone instance
  s.unionWeight = 2;
  s.unionGroup = 3;
  const DirectOptimizer opt(grid, s);
  OptimizerState full = opt.initialState();
  opt.run(full, s.epochs);
  OptimizerState part = opt.initialState();
  opt.run(part, 17);
  opt.run(part, s.epochs);
  EXPECT_EQ(part.params, full.params);
  OptimizerState independent = opt.initialState();
  OptimizerSettings off = s;
  off.unionWeight = 0;
  DirectOptimizer(grid, off).run(independent, s.epochs);
  EXPECT_NE(independent.params, full.params);
}

// The environment maps' preset (sphere-exact): a bank for a map with a sun
// (one cell 1e4 times the sky's) lowers every instance's grid L2asd and its
// union's from the Owen-Sobol start, with no NaN on the way, and comes out
// bit-identical on one core and on two: its instances run in parallel, and
// each one's sums keep their order.
TEST(DirectOptimizer, SphereExactPresetOnASunnyMap) {
  std::vector<double> density(16 * 8, 1.0);
  density[3 * 16 + 5] = 1e4;                             // the sun
  for (int i = 0; i < 16; ++i) density[7 * 16 + i] = 0;  // a black row under the horizon
  const GridTarget map(GridTarget::uniformEdges(16), GridTarget::uniformEdges(8), density,
                       "envmap:sun", Domain::Sphere, "test");
  OptimizerSettings s = presetSettings("sphere-exact", 16);
  EXPECT_EQ(s.objective, Objective::ExactL2asd);
  EXPECT_GT(s.unionWeight, 0);
  s.epochs = 120;
  s.instances = 8;
  s.seed = 11;
  s.validate();
  const DirectOptimizer opt(map, s);
  const auto optimized = [&](int threads) {
    tbb::global_control cores(tbb::global_control::max_allowed_parallelism, threads);
    OptimizerState state = opt.initialState();
    opt.run(state, s.epochs, [](const EpochReport &r) {
      ASSERT_TRUE(std::isfinite(r.loss) && std::isfinite(r.unionLoss));
    });
    return state;
  };
  const OptimizerState one = optimized(1), two = optimized(2);
  EXPECT_EQ(one.params, two.params);
  const PointSet start = opt.points(opt.initialState()), end = opt.points(two);
  for (std::size_t k = 0; k < s.instances; ++k)
    EXPECT_LT(nonuniformL2asd(end.instance(k), map), nonuniformL2asd(start.instance(k), map))
        << "instance " << k;
  EXPECT_LT(nonuniformL2asd(end.points, map), nonuniformL2asd(start.points, map));
  for (const Point2 &p : end.points) ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y));
}

// Nested sets: the loss of epoch 1 is the full set's closed-form L2asd plus
// (m / n)^p times each power-of-2 prefix's, by brute force at the starting
// points; Adam's first step moves every coordinate against the sign of that
// loss's central difference (the nested gradient's sign, component by
// component); and after optimization the prefixes beat those of an unnested
// run while the full set stays within 10 %.
TEST(DirectOptimizer, NestedSetsOptimizeEveryPrefix) {
  const UniformTarget uniform;
  OptimizerSettings s = small(32, 1);
  s.objective = Objective::ExactL2asd;
  s.instances = 1;
  s.nestedSizes = nestedChain(4, 32);
  s.nestedPower = 2;
  EXPECT_EQ(s.prefixSizes(), (std::vector<std::size_t>{4, 8, 16, 32}));
  const auto nestedLoss = [&](std::span<const Point2> p) {
    double loss = closedFormL2asdSquared(p);
    for (std::size_t m : {4, 8, 16})
      loss += std::pow(double(m) / 32, s.nestedPower) * closedFormL2asdSquared(p.first(m));
    return loss;
  };
  const DirectOptimizer opt(uniform, s);
  OptimizerState state = opt.initialState();
  const std::vector<Point2> start = state.params;
  double reported = 0;
  opt.run(state, 1, [&](const EpochReport &r) { reported = r.loss; });
  EXPECT_NEAR(reported, nestedLoss(start), 1e-12 * nestedLoss(start));
  std::vector<Point2> p = start;
  int checked = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int k = 0; k < 2; ++k) {
      const double x0 = p[i][k], h = 1e-6;
      p[i][k] = x0 + h;
      const double up = nestedLoss(p);
      p[i][k] = x0 - h;
      const double down = nestedLoss(p);
      p[i][k] = x0;
      const double fd = (up - down) / (2 * h), step = state.params[i][k] - x0;
      if (std::abs(fd) < 1e-6) continue;  // a flat direction: Adam's sign is noise
      EXPECT_LT(fd * step, 0) << "point " << i << " axis " << k << ": fd " << fd;
      ++checked;
    }
  EXPECT_GT(checked, 40);

  // Optimized for 400 epochs, nested against not.
  s.epochs = 400;
  s.instances = 4;
  OptimizerSettings flat = s;
  flat.nestedSizes.clear();
  const auto run = [&](const OptimizerSettings &settings) {
    const DirectOptimizer o(uniform, settings);
    OptimizerState st = o.initialState();
    o.run(st, settings.epochs);
    return o.points(st);
  };
  const PointSet nested = run(s), plain = run(flat);
  EXPECT_EQ(findMeta(nested, meta::kPrefixes) ? *findMeta(nested, meta::kPrefixes) : "",
            "4,8,16,32");
  EXPECT_EQ(findMeta(plain, meta::kPrefixes), nullptr);
  const auto prefixL2asd = [](const PointSet &set, std::size_t m) {
    double sum = 0;
    for (std::size_t k = 0; k < set.instances(); ++k) sum += l2asd(set.instance(k).first(m));
    return sum / double(set.instances());
  };
  for (std::size_t m : {4, 8})
    EXPECT_LT(prefixL2asd(nested, m), prefixL2asd(plain, m)) << "prefix " << m;
  EXPECT_LT(prefixL2asd(nested, 32), 1.1 * prefixL2asd(plain, 32));
}

TEST(DirectOptimizer, RejectsBadSettings) {
  const UniformTarget u;
  OptimizerSettings s = small(10, 10);
  s.lrStart = -1;
  EXPECT_THROW(DirectOptimizer(u, s), std::invalid_argument);
  s = small(10, 10);
  s.rampFraction = 2;
  EXPECT_THROW(DirectOptimizer(u, s), std::invalid_argument);
  EXPECT_THROW(presetSettings("fast", 10), std::invalid_argument);
  const QuarterDiscTarget disc;
  s = small(10, 10);
  s.objective = Objective::ExactL2asd;
  EXPECT_THROW(DirectOptimizer(disc, s), std::invalid_argument);  // neither uniform nor a grid
  // The bank term: l2asd only, >= 2 instances, groups of >= 2, a weight >= 0.
  s = small(10, 10);
  s.unionWeight = 1;
  EXPECT_THROW(DirectOptimizer(u, s), std::invalid_argument);  // soft boxes
  s.objective = Objective::ExactL2asd;
  EXPECT_NO_THROW(DirectOptimizer(u, s));
  s.instances = 1;
  EXPECT_THROW(DirectOptimizer(u, s), std::invalid_argument);
  s.instances = 4;
  s.unionGroup = 1;
  EXPECT_THROW(DirectOptimizer(u, s), std::invalid_argument);
  s.unionGroup = 2;
  s.unionWeight = -1;
  EXPECT_THROW(DirectOptimizer(u, s), std::invalid_argument);
  s.unionWeight = std::nan("");
  EXPECT_THROW(DirectOptimizer(u, s), std::invalid_argument);
  // Nested prefixes: ascending sizes below n, a finite power >= 0.
  for (const auto &[sizes, power] : std::vector<std::pair<std::vector<std::size_t>, double>>{
           {{0}, 1}, {{16}, 1}, {{8, 4}, 1}, {{4, 4}, 1}, {{4}, -1}, {{4}, NAN}}) {
    s = small(16, 10);
    s.nestedSizes = sizes;
    s.nestedPower = power;
    EXPECT_THROW(DirectOptimizer(u, s), std::invalid_argument) << power;
  }
  s = small(16, 10);
  s.nestedSizes = {3, 8};
  EXPECT_NO_THROW(DirectOptimizer(u, s));
  EXPECT_NE(s.describe().find(" nested=3,8^1"), std::string::npos) << s.describe();
  EXPECT_EQ(nestedChain(4, 64), (std::vector<std::size_t>{4, 8, 16, 32}));
  EXPECT_TRUE(nestedChain(64, 64).empty());
  EXPECT_EQ(small(16, 10).describe().find("nested"), std::string::npos)
      << "unnested settings keep their old description (cache keys, checkpoints)";
}

}  // namespace
}  // namespace nuld

namespace nuld {
namespace {

// The non-uniform objective: its value is the metric, it reduces to the
// uniform closed form, and its gradient matches central differences.
TEST(NonuniformL2asdObjective, ValueGradientAndUniformLimit) {
  const PointSet set = generatePointSet({SequenceKind::Random, Scramble::None, 9}, 19, 1);
  std::vector<Point2> pts = set.points, grad(pts.size()), uniformGrad(pts.size());
  const UniformTarget uniform;
  const NonuniformL2asd onUniform(uniform, 8);
  EXPECT_NEAR(onUniform.squared(pts, grad), closedFormL2asdSquared(pts, uniformGrad), 1e-15);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_NEAR(grad[i].x, uniformGrad[i].x, 1e-13);
    EXPECT_NEAR(grad[i].y, uniformGrad[i].y, 1e-13);
  }
  std::vector<double> density = {1, 0, 3, 2, 0.5, 4, 1, 1, 0, 2, 2, 7};
  const GridTarget grid({0, 0.3, 0.45, 1}, {0, 0.2, 0.5, 0.9, 1}, density, "grid", Domain::Square,
                        "test");
  const NonuniformL2asd objective(grid);
  const double value = objective.squared(pts, grad);
  EXPECT_NEAR(std::sqrt(value), nonuniformL2asd(pts, grid), 1e-15);
  // Piecewise smooth: central differences are accurate unless a kink (another
  // point's coordinate or a cell edge) lies within h.
  expectCentralDifferences(objective, pts, grad, 1e-6, 1e-6, 1e-9);
}

}  // namespace
}  // namespace nuld
