// The graph generator (--arch graph): its neighbour graph against brute
// force, the untrained net is its base set, permuting the points permutes
// the output, it makes and trains on sets of several sizes, and its model
// files round-trip and fail clearly.

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "sampler/metrics/discrepancy.h"
#include "sampler/neural/network.h"
#include "sampler/neural/neural_trainer.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sobol.h"
#include "tests/common/temp_dir.h"
#include "tests/neural/expect_load_error.h"
#include "tests/neural/tiny_settings.h"

namespace nuld {
namespace {

NeuralSettings tinyGraph(const std::string &family, std::size_t n, bool mapped = true) {
  NeuralSettings s = test::tinyNeuralSettings(family, n, 12, mapped, 7);
  s.arch = NetworkArch::Graph;
  s.neighbours = 5;
  s.rounds = 2;
  return s;
}

// Four large steps on small batches: enough to make the last layer non-zero.
TrainerSettings fourQuickSteps() {
  TrainerSettings t;
  t.steps = 4;
  t.batch = 2;
  t.boxes = 128;
  t.lrStart = t.lrEnd = 1e-2;
  t.validationSets = 0;
  return t;
}

std::vector<Point2> randomPoints(std::size_t n, std::uint64_t seed) {
  Rng rng(seed, 1);
  std::vector<Point2> p(n);
  for (Point2 &q : p) q = {rng.uniform(), rng.uniform()};
  return p;
}

TEST(TorusGraph, EqualsBruteForceNearestNeighbours) {
  for (const std::size_t n : {1, 2, 3, 9, 300, 1500}) {
    const std::vector<Point2> p = randomPoints(n, n);
    const TorusGraph g = buildTorusGraph(p, 8);
    ASSERT_EQ(g.k, std::min<std::size_t>(8, n - 1)) << n;
    for (std::size_t i = 0; i < n; ++i) {
      std::vector<std::pair<double, std::int64_t>> all;
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i) continue;
        // Brute force over the nine images of j around the unit square.
        double best = 1e9;
        for (int sx = -1; sx <= 1; ++sx)
          for (int sy = -1; sy <= 1; ++sy)
            best = std::min(best, std::hypot(p[j].x + sx - p[i].x, p[j].y + sy - p[i].y));
        all.push_back({best, std::int64_t(j)});
      }
      std::sort(all.begin(), all.end());
      for (std::size_t e = 0; e < g.k; ++e) {
        ASSERT_EQ(g.neighbours[i * g.k + e], all[e].second) << n << " " << i << " " << e;
        const Point2 d = g.offsets[i * g.k + e];
        EXPECT_NEAR(std::hypot(d.x, d.y), all[e].first, 1e-12);
        EXPECT_TRUE(d.x >= -0.5 && d.x < 0.5 && d.y >= -0.5 && d.y < 0.5);
      }
    }
  }
}

TEST(GraphGenerator, UntrainedOutputIsTheBaseSetThroughTheTarget) {
  for (const std::size_t n : {1, 37}) {
    const NeuralGenerator gen(tinyGraph("family:gaussian", n));
    const std::vector<double> gamma = {0.2, 0.7, 0.4, 0.9, 0.1, 0.6};
    const std::vector<Point2> z = {{0.61, 0.05}, {0.999, 0.3}};
    std::vector<Point2> base(n), out(2 * n);
    gen.generate(z, gamma, out);
    for (std::size_t k = 0; k < 2; ++k) {
      const auto target = gen.family().target(std::span(gamma).subspan(3 * k, 3));
      gen.baseSet(z[k], base);
      for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(out[k * n + i], target->invert(base[i]).x);
    }
  }
}

// The Owen base: each z gives its own scrambling of the first N Sobol
// points (a (0, m, 2)-net: one point per 1/N-wide column and row), the same
// z the same set, and the untrained net returns it through the target.
TEST(GraphGenerator, OwenBaseIsAScrambledNetPerOffset) {
  const std::size_t n = 64;
  NeuralSettings s = tinyGraph("quarterdisc", n);
  s.base = BaseRandomization::Owen;
  const NeuralGenerator gen(s);
  const std::vector<Point2> z = {{0.25, 0.5}, {0.25, 0.5000001}};
  std::vector<Point2> a(n), b(n), again(n), out(2 * n);
  gen.baseSet(z[0], a);
  gen.baseSet(z[1], b);
  gen.baseSet(z[0], again);
  EXPECT_EQ(a, again);
  for (const std::vector<Point2> *set : {&a, &b}) {
    std::vector<int> columns(n), rows(n);
    for (const Point2 &p : *set) ++columns[std::size_t(p.x * n)], ++rows[std::size_t(p.y * n)];
    EXPECT_EQ(std::count(columns.begin(), columns.end(), 1), std::ptrdiff_t(n));
    EXPECT_EQ(std::count(rows.begin(), rows.end(), 1), std::ptrdiff_t(n));
  }
  std::size_t same = 0;
  for (std::size_t i = 0; i < n; ++i) same += a[i] == b[i];
  EXPECT_EQ(same, 0u);  // nearby offsets, unrelated scramblings
  gen.generate(z, {}, out);
  const auto target = gen.family().target({});
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(out[i], target->invert(a[i]).x);
    EXPECT_EQ(out[n + i], target->invert(b[i]).x);
  }
}

// Equivariance: the same per-point inputs in another order, with the graph
// rebuilt from the reordered points, give the same residuals reordered.
TEST(GraphGenerator, PermutingThePointsPermutesTheOutput) {
  const std::size_t n = 40, k = 6;
  const std::int64_t F = 5;
  torch::manual_seed(3);
  GraphNet net(torch::zeros({0, 0}), F, 4, 16, 3);
  {
    torch::NoGradGuard noGrad;
    net->out->weight.normal_(0, 1);
    net->out->bias.normal_(0, 1);
  }
  const std::vector<Point2> p = randomPoints(n, 11);
  const torch::Tensor features = torch::randn({1, std::int64_t(n), F});
  std::vector<std::size_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(5));
  auto run = [&](const std::vector<Point2> &points, const torch::Tensor &nodes) {
    const TorusGraph g = buildTorusGraph(points, k);
    torch::Tensor edges = torch::empty({1, std::int64_t(n), std::int64_t(k), 4});
    for (std::size_t e = 0; e < n * k; ++e) {
      const Point2 d = g.offsets[e];
      edges[0][std::int64_t(e / k)][std::int64_t(e % k)] =
          torch::tensor({float(d.x), float(d.y), float(d.x * d.y), float(d.x - d.y)});
    }
    const torch::Tensor nb = torch::from_blob(const_cast<std::int64_t *>(g.neighbours.data()),
                                              {std::int64_t(n * k)}, torch::kInt64)
                                 .clone();
    torch::NoGradGuard noGrad;
    return net->forward(nodes, edges, nb);
  };
  std::vector<Point2> q(n);
  std::vector<std::int64_t> index(n);
  for (std::size_t i = 0; i < n; ++i) q[i] = p[perm[i]], index[i] = std::int64_t(perm[i]);
  const torch::Tensor a = run(p, features);
  const torch::Tensor b = run(q, features.index_select(1, torch::tensor(index)));
  EXPECT_GT(a.abs().max().item<double>(), 0.1);
  EXPECT_LE((b - a.index_select(1, torch::tensor(index))).abs().max().item<double>(), 1e-5);
}

TEST(GraphGenerator, TrainedWeightsSaveAndLoadBitExactly) {
  test::TempDir dir;
  NeuralGenerator gen(tinyGraph("quarterdisc", 24));
  TrainerSettings t = fourQuickSteps();
  const auto trainer = NeuralTrainer::make(gen, t);
  trainer->run(4);
  const std::string path = (dir / "g.nuldnet").string();
  gen.save(path);
  const NeuralGenerator back = NeuralGenerator::load(path);
  EXPECT_EQ(back.settings().arch, NetworkArch::Graph);
  EXPECT_EQ(back.settings().neighbours, 5);
  EXPECT_EQ(back.settings().rounds, 2);
  EXPECT_EQ(back.settings().positionHarmonics, gen.settings().positionHarmonics);
  const auto pa = torchNet(gen).module().parameters(), pb = torchNet(back).module().parameters();
  ASSERT_EQ(pa.size(), pb.size());
  for (std::size_t i = 0; i < pa.size(); ++i) EXPECT_TRUE(torch::equal(pa[i], pb[i])) << i;
  EXPECT_GT(torchNet(gen).graph->out->weight.abs().max().item<float>(), 0);  // trained
  const PointSet a = gen.generateSets(3, 9, {}), b = back.generateSets(3, 9, {});
  EXPECT_EQ(a.points, b.points);
  const PointSet base = NeuralGenerator(tinyGraph("quarterdisc", 24)).generateSets(3, 9, {});
  EXPECT_NE(a.points, base.points);
}

TEST(GraphGenerator, OwenBaseSavesAndLoadsAndOldFilesAreRotated) {
  test::TempDir dir;
  NeuralSettings s = tinyGraph("quarterdisc", 16);
  s.base = BaseRandomization::Owen;
  const NeuralGenerator gen(s);
  gen.save((dir / "owen").string());
  const NeuralGenerator back = NeuralGenerator::load((dir / "owen").string());
  EXPECT_EQ(back.settings().base, BaseRandomization::Owen);
  EXPECT_EQ(back.generateSets(2, 3, {}).points, gen.generateSets(2, 3, {}).points);
  ModelFile file = gen.toModelFile();
  file.metadata.erase("base");  // files from before the Owen base
  writeModelFile((dir / "old").string(), file);
  EXPECT_EQ(NeuralGenerator::load((dir / "old").string()).settings().base,
            BaseRandomization::Rotated);
  file.metadata["base"] = "halton";
  writeModelFile((dir / "bad").string(), file);
  test::expectLoadError((dir / "bad").string(), "metadata 'base' is 'halton', expected");

  NeuralSettings supplement = test::tinyNeuralSettings("quarterdisc", 8, 8, true, 1);
  supplement.base = BaseRandomization::Owen;  // its residuals are functions of z
  EXPECT_THROW(NeuralGenerator{supplement}, std::invalid_argument);
  s.offsetRange = 0.5;
  EXPECT_THROW(NeuralGenerator{s}, std::invalid_argument);
  EXPECT_THROW(parseBaseRandomization("sobol"), std::invalid_argument);
}

// Weights shared by all points: a graph model makes sets of any size. The
// untrained model returns its base set at that size (for the rotated base
// the first N Sobol points rotated by z, for the Owen base the scrambled
// net), a trained one finite points in the domain; the supplement's network
// makes its own N only and says so.
TEST(GraphGenerator, MakesSetsOfAnySize) {
  for (const BaseRandomization base : {BaseRandomization::Rotated, BaseRandomization::Owen}) {
    NeuralSettings s = tinyGraph("quarterdisc", 16);
    s.base = base;
    const NeuralGenerator gen(s);
    const auto target = gen.family().target({});
    for (const std::size_t n : {1, 2, 37, 100}) {
      const std::vector<Point2> z = {{0.3, 0.8}, {0.71, 0.02}};
      std::vector<Point2> out(2 * n), base1(n);
      gen.generate(z, {}, n, out);
      for (std::size_t k = 0; k < 2; ++k) {
        gen.baseSet(z[k], base1);
        for (std::size_t i = 0; i < n; ++i)
          ASSERT_EQ(out[k * n + i], target->invert(base1[i]).x) << n << " " << i;
      }
      if (base == BaseRandomization::Rotated) {
        const Point2 last{sobolSample(n - 1, 0) + 0.71, sobolSample(n - 1, 1) + 0.02};
        EXPECT_EQ(base1.back().x, last.x - std::floor(last.x)) << n;
      }
      EXPECT_EQ(gen.generateSets(3, 5, {}, n).points.size(), 3 * n);
    }
  }
  NeuralGenerator trained(tinyGraph("quarterdisc", 24));
  TrainerSettings t = fourQuickSteps();
  NeuralTrainer::make(trained, t)->run(4);
  for (const std::size_t n : {1, 50, 300}) {
    const PointSet set = trained.generateSets(2, 9, {}, n);
    ASSERT_EQ(set.n, n);
    for (const Point2 &p : set.points)
      EXPECT_TRUE(isFinite(p) && p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1);
  }
  EXPECT_NE(trained.generateSets(1, 9, {}, 50).points,
            NeuralGenerator(tinyGraph("quarterdisc", 24)).generateSets(1, 9, {}, 50).points);

  const NeuralGenerator supplement(test::tinyNeuralSettings("quarterdisc", 8, 8, true, 1));
  EXPECT_FALSE(supplement.anySize());
  EXPECT_NO_THROW(supplement.checkSize(8));
  try {
    supplement.checkSize(9);
    FAIL();
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("makes sets of 8 points only, not 9"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(trained.checkSize(0), std::invalid_argument);
}

// Several training sizes: steps cycle through them, the held-out score is the
// geometric mean of each size's mean L2, the file records them, and a
// checkpoint of a single-size run is refused.
TEST(GraphGenerator, TrainsOnSeveralSizes) {
  test::TempDir dir;
  NeuralSettings s = tinyGraph("quarterdisc", 16);
  s.base = BaseRandomization::Owen;
  s.trainingNs = {16, 40};
  NeuralGenerator gen(s);
  TrainerSettings t = fourQuickSteps();
  t.validationSets = 4;
  t.validationGrid = 64;
  const auto trainer = NeuralTrainer::make(gen, t);
  EXPECT_EQ(trainer->sizeAt(0), 16u);
  EXPECT_EQ(trainer->sizeAt(1), 40u);
  EXPECT_EQ(trainer->sizeAt(2), 16u);
  trainer->run(4);
  std::vector<Point2> z;
  std::vector<double> gamma;
  trainer->validationInputs(z, gamma);
  const auto target = gen.family().target({});
  double mean16 = 0, mean40 = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const std::size_t n = k % 2 == 0 ? 16 : 40;
    std::vector<Point2> points(n);
    gen.generate(std::span(z).subspan(k, 1), {}, n, points);
    (n == 16 ? mean16 : mean40) += nonuniformL2asd(points, *target, 64) / 2;
  }
  // (Sets made one at a time here: float summation order differs slightly.)
  EXPECT_NEAR(trainer->validate().l2, std::sqrt(mean16 * mean40), 1e-6 * mean16);

  const std::string path = (dir / "multi.nuldnet").string();
  gen.save(path);
  EXPECT_EQ(gen.metadata().at("training_n"), "16,40");
  EXPECT_EQ(NeuralGenerator::load(path).settings().trainingNs, (std::vector<std::size_t>{16, 40}));
  EXPECT_EQ(NeuralGenerator(tinyGraph("quarterdisc", 16)).metadata().count("training_n"), 0u);
  ModelFile file = gen.toModelFile();
  file.metadata["training_n"] = "16,x";
  writeModelFile((dir / "bad").string(), file);
  test::expectLoadError((dir / "bad").string(), "training_n");

  const std::string ckpt = (dir / "single.ckpt").string();
  NeuralGenerator single(tinyGraph("quarterdisc", 16));
  NeuralTrainer::make(single, t)->saveCheckpoint(ckpt);
  EXPECT_THROW(trainer->loadCheckpoint(ckpt), std::runtime_error);

  t.validationSets = 1;
  EXPECT_THROW(NeuralTrainer::make(gen, t), std::invalid_argument);  // a size never validated
  NeuralSettings bad = s;
  bad.trainingNs = {40, 16};  // n must come first
  EXPECT_THROW(NeuralGenerator{bad}, std::invalid_argument);
  bad = test::tinyNeuralSettings("quarterdisc", 16, 8, true, 1);
  bad.trainingNs = {16, 40};  // the supplement's network emits a fixed N
  EXPECT_THROW(NeuralGenerator{bad}, std::invalid_argument);
}

TEST(GraphGenerator, BadArchitectureMetadataAndSettingsAreClearErrors) {
  test::TempDir dir;
  using test::expectLoadError;
  const NeuralGenerator gen(tinyGraph("quarterdisc", 8));
  ModelFile file = gen.toModelFile();
  file.metadata["arch"] = "transformer";
  writeModelFile((dir / "arch").string(), file);
  expectLoadError((dir / "arch").string(), "expected supplement or graph");
  file = gen.toModelFile();
  file.metadata.erase("rounds");
  writeModelFile((dir / "rounds").string(), file);
  expectLoadError((dir / "rounds").string(), "rounds");
  file = gen.toModelFile();
  file.metadata["arch"] = "supplement";  // a graph's weights under the MLP's name
  writeModelFile((dir / "mismatch").string(), file);
  expectLoadError((dir / "mismatch").string(), "wrong shape");

  // A file from before the graph generator (no 'arch') is the supplement's.
  NeuralSettings old = test::tinyNeuralSettings("quarterdisc", 8, 8, true, 1);
  file = NeuralGenerator(old).toModelFile();
  file.metadata.erase("arch");
  writeModelFile((dir / "old").string(), file);
  EXPECT_EQ(NeuralGenerator::load((dir / "old").string()).settings().arch, NetworkArch::Supplement);

  NeuralSettings s = tinyGraph("quarterdisc", 8);
  s.zHarmonics = 2;
  EXPECT_THROW(NeuralGenerator{s}, std::invalid_argument);
  s = tinyGraph("quarterdisc", 8);
  s.neighbours = 0;
  EXPECT_THROW(NeuralGenerator{s}, std::invalid_argument);
  EXPECT_THROW(parseNetworkArch("mlp"), std::invalid_argument);
}

}  // namespace
}  // namespace nuld
