// Training: the custom autograd function's gradient through the whole net
// against finite differences, the loss falls, checkpoints resume exactly,
// and trained weights survive save/load bit-exactly.

#include "sampler/neural/neural_trainer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sampler/metrics/discrepancy.h"
#include "sampler/neural/network.h"
#include "sampler/targets/target_spec.h"
#include "tests/common/temp_dir.h"
#include "tests/neural/test_families.h"
#include "tests/neural/tiny_settings.h"

namespace nuld {
namespace {

NeuralSettings tinyNet(const std::string &family, std::size_t n, int hidden, bool mapped = true) {
  return test::tinyNeuralSettings(family, n, hidden, mapped, 3);
}

TrainerSettings tinyTraining(int steps) { return test::tinyTrainerSettings(steps, 11); }

// Central differences of the step loss in double precision against the
// gradient the custom function hands to autograd, for weights and biases of
// every layer. The last layer starts at zero, which would zero every earlier
// layer's gradient; it is randomized first. Unmapped on the square, a clamped
// point's gradient passes straight through by design, which differences
// cannot see, so that case uses N = 1 (one point, at z, kept inside); the
// sphere case moves 9 points per set across the poles; the mapped cases go
// through the targets' inverse CDFs.
void checkGradient(const std::string &family, std::size_t n, double lastLayerScale, bool mapped,
                   NetworkArch arch = NetworkArch::Supplement,
                   BaseRandomization base = BaseRandomization::Rotated) {
  SCOPED_TRACE(family + " base " + toString(base));
  NeuralSettings settings = tinyNet(family, n, 6, mapped);
  settings.arch = arch;
  settings.base = base;
  settings.neighbours = 3;
  settings.rounds = 2;
  NeuralGenerator gen(settings);
  torch::nn::Module &net = torchNet(gen).module();
  net.to(torch::kFloat64);
  {
    torch::NoGradGuard noGrad;
    torch::manual_seed(1);
    const torch::nn::Linear last =
        arch == NetworkArch::Graph ? torchNet(gen).graph->out : torchNet(gen).mlp->l5;
    last->weight.normal_(0, lastLayerScale);
    last->bias.normal_(0, lastLayerScale);
  }
  TrainerSettings t = tinyTraining(10);
  t.alphaStart = t.alphaEnd = 8;         // smooth enough for differences of 1e-6
  t.pullback = GradientPullback::Exact;  // the true gradient, which differences measure
  const auto trainer = NeuralTrainer::make(gen, t);
  trainer->lossAndGradient(2);
  int checked = 0;
  for (auto &item : net.named_parameters()) {
    torch::Tensor p = item.value();
    const torch::Tensor grad = p.grad().clone();
    const double scale = grad.abs().max().item<double>();
    EXPECT_GT(scale, 0) << item.key();
    auto flat = p.view({-1});
    for (std::int64_t i = 0; i < flat.numel(); i += std::max<std::int64_t>(1, flat.numel() / 5)) {
      const double h = 1e-6, w = flat[i].item<double>();
      double plus, minus;
      {
        torch::NoGradGuard noGrad;
        flat[i] = w + h;
      }
      plus = trainer->evaluate(2);
      {
        torch::NoGradGuard noGrad;
        flat[i] = w - h;
      }
      minus = trainer->evaluate(2);
      {
        torch::NoGradGuard noGrad;
        flat[i] = w;
      }
      const double fd = (plus - minus) / (2 * h), an = grad.view({-1})[i].item<double>();
      // The floor is relative to the tensor's largest gradient, so it scales
      // with layers whose gradients are small (never an absolute pass).
      EXPECT_NEAR(an, fd, 1e-3 * std::abs(fd) + 1e-6 * scale) << item.key() << "[" << i << "]";
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);
}

TEST(NeuralTrainer, GradientThroughTheNetMatchesFiniteDifferencesOnTheSquare) {
  checkGradient("family:gaussian", 1, 1e-3, false);
}

TEST(NeuralTrainer, GradientThroughTheNetAndTheInverseCdfMatchesFiniteDifferences) {
  // Mapped: the loss sees T(u), and the gradient passes T's Jacobian.
  checkGradient("family:gaussian", 9, 0.05, true);
  checkGradient("family:bilinear", 9, 0.05, true);
}

TEST(NeuralTrainer, GradientThroughTheNetMatchesFiniteDifferencesThroughThePoles) {
  test::registerTestSphereFamily();
  checkGradient("family:test-sphere", 9, 0.05, false);
}

// The graph generator: every layer of every round, messages included, with
// and without gamma, through the inverse CDF and through the poles. The
// inputs (features of the base set) carry no gradient; the points do.
TEST(NeuralTrainer, GradientThroughTheGraphNetMatchesFiniteDifferences) {
  checkGradient("family:gaussian", 9, 0.5, true, NetworkArch::Graph);
  checkGradient("quarterdisc", 11, 0.5, true, NetworkArch::Graph);
  test::registerTestSphereFamily();
  checkGradient("family:test-sphere", 9, 0.5, false, NetworkArch::Graph);
  // An Owen base: every set of the batch has its own neighbour graph. On the
  // sphere the residuals are kept small: at 0.5 the embedding's differences
  // disagree by 1 %, as where a moved point meets a kink (the pole
  // reflection or the clamp of its box); at 0.05 they agree.
  checkGradient("quarterdisc", 11, 0.5, true, NetworkArch::Graph, BaseRandomization::Owen);
  checkGradient("family:test-sphere", 9, 0.05, false, NetworkArch::Graph, BaseRandomization::Owen);
}

// Balanced pull-back: each point's u-gradient component k is the exact one
// (J^T g, checked against differences above) divided by |column k of J|.
// Checked on the untrained quarter-disc net, whose points are T(base set),
// through the last layer's bias gradient, which is the mean u-gradient over
// the batch (batch 1 here, so each point's own). The rim of the disc
// stretches T by far more than 1, so the rescaling is not a no-op.
TEST(NeuralTrainer, BalancedPullbackDividesEachComponentByItsJacobianColumn) {
  const std::size_t n = 64;
  auto biasGradient = [&](GradientPullback pullback) {
    NeuralGenerator gen(tinyNet("quarterdisc", n, 6));
    torchNet(gen).mlp->to(torch::kFloat64);
    TrainerSettings t = tinyTraining(10);
    t.batch = 1;
    t.pullback = pullback;
    const auto trainer = NeuralTrainer::make(gen, t);
    trainer->lossAndGradient(3);
    std::vector<Point2> z;
    std::vector<double> gamma;
    trainer->batchInputs(3, z, gamma);
    std::vector<Point2> base(n);
    gen.baseSet(z[0], base);
    return std::pair{torchNet(gen).mlp->l5->bias.grad().clone(), base};
  };
  const auto [exact, base] = biasGradient(GradientPullback::Exact);
  const auto [balanced, unused] = biasGradient(GradientPullback::Balanced);
  const auto target = makeTarget("quarterdisc");
  double largestColumn = 0;
  int nonzero = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Jacobian2 j = target->invert({wrapUnit(base[i].x), wrapUnit(base[i].y)}).jacobian;
    for (int k = 0; k < 2; ++k) {
      const double column = std::hypot(j.m[0][k], j.m[1][k]);
      largestColumn = std::max(largestColumn, column);
      const double e = exact[std::int64_t(2 * i + k)].item<double>();
      const double b = balanced[std::int64_t(2 * i + k)].item<double>();
      EXPECT_NEAR(b * column, e, 1e-12 * std::abs(e) + 1e-300) << "point " << i << " axis " << k;
      nonzero += e != 0;
    }
  }
  EXPECT_GT(largestColumn, 3);
  EXPECT_GT(nonzero, int(n));
}

TEST(NeuralTrainer, UnknownPullbackIsRefusedByName) {
  EXPECT_EQ(parseGradientPullback("balanced"), GradientPullback::Balanced);
  EXPECT_EQ(toString(parseGradientPullback("exact")), "exact");
  try {
    parseGradientPullback("natural");
    FAIL() << "accepted 'natural'";
  } catch (const std::invalid_argument &e) {
    EXPECT_EQ(std::string(e.what()),
              "unknown gradient pull-back 'natural' (expected exact or balanced)");
  }
}

TEST(NeuralTrainer, LossFallsOnATinyConfiguration) {
  NeuralGenerator gen(tinyNet("quarterdisc", 16, 32));
  const auto trainer = NeuralTrainer::make(gen, tinyTraining(150));
  // Held-out batches: step indices the run never trains on.
  auto heldOut = [&] {
    double sum = 0;
    for (int s = 1000; s < 1008; ++s) sum += trainer->evaluate(s);
    return sum / 8;
  };
  const double before = heldOut();
  const double l2Before = trainer->validate().l2;
  trainer->run(150);
  const double after = heldOut();
  EXPECT_LT(after, 0.5 * before) << before << " -> " << after;
  // The held-out discrepancy, which no alpha or batch moves, falls too.
  const Validation v = trainer->validate();
  EXPECT_LT(v.l2, l2Before);
  EXPECT_EQ(v.step, 150);
  EXPECT_TRUE(std::isfinite(v.meanLoss) && v.meanLoss > 0);
  EXPECT_EQ(trainer->best()->step, 150);
}

// validate() is the mean grid L2 of the generator's own sets at the held-out
// pairs, each against its gamma's target: checked by generating them here.
// For an untrained mapped net those are inverse-CDF rotated Sobol sets.
TEST(NeuralTrainer, ValidationIsTheMeanGridL2AtTheHeldOutPairs) {
  NeuralGenerator gen(tinyNet("family:bilinear", 16, 8));
  TrainerSettings t = tinyTraining(4);
  t.validationSets = 3;
  t.validationGrid = 64;
  const auto trainer = NeuralTrainer::make(gen, t);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<Point2> z;
    std::vector<double> gamma;
    trainer->validationInputs(z, gamma);
    ASSERT_EQ(z.size(), 3u);
    ASSERT_EQ(gamma.size(), 3 * gen.gammaDimension());
    std::vector<Point2> points(3 * 16);
    gen.generate(z, gamma, points);
    double sum = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      const auto target = gen.family().target(std::span(gamma).subspan(k * 4, 4));
      sum += nonuniformL2asd(std::span(points).subspan(k * 16, 16), *target, 64);
    }
    const Validation v = trainer->validate();
    EXPECT_DOUBLE_EQ(v.l2, sum / 3) << "pass " << pass;
    EXPECT_EQ(std::isnan(v.meanLoss), pass == 0) << "no step ran before the first";
    trainer->run(2 * (pass + 1));
  }
  EXPECT_EQ(trainer->history().size(), 2u);
  t.validationSets = 0;
  const auto off = NeuralTrainer::make(gen, t);
  EXPECT_THROW(off->validate(), std::logic_error);
}

// The validation history and the losses since the last validation travel in
// the checkpoint, so a resumed run reports what the uninterrupted one does.
TEST(NeuralTrainer, ValidationHistoryResumesExactly) {
  test::TempDir dir;
  const std::string ckpt = (dir / "run.ckpt").string();
  TrainerSettings t = tinyTraining(6);
  t.validationSets = 2;
  NeuralGenerator straight(tinyNet("quarterdisc", 8, 8));
  const auto a = NeuralTrainer::make(straight, t);
  a->validate();
  a->run(3);
  a->validate();
  a->run(6);
  a->validate();

  NeuralGenerator first(tinyNet("quarterdisc", 8, 8));
  const auto b = NeuralTrainer::make(first, t);
  b->validate();
  b->run(3);
  b->validate();
  b->run(4);  // one loss since the last validation
  b->saveCheckpoint(ckpt);
  NeuralGenerator resumed(tinyNet("quarterdisc", 8, 8));
  const auto c = NeuralTrainer::make(resumed, t);
  c->loadCheckpoint(ckpt);
  ASSERT_EQ(c->history().size(), 2u);
  c->run(6);
  c->validate();
  ASSERT_EQ(c->history().size(), a->history().size());
  for (std::size_t i = 0; i < a->history().size(); ++i) {
    EXPECT_EQ(c->history()[i].step, a->history()[i].step);
    EXPECT_EQ(c->history()[i].l2, a->history()[i].l2) << i;
    if (i > 0) {
      EXPECT_EQ(c->history()[i].meanLoss, a->history()[i].meanLoss) << i;
    }
  }
  EXPECT_EQ(c->best()->step, a->best()->step);
}

TEST(NeuralTrainer, ResumedRunEndsBitIdenticalAndSaveLoadIsExact) {
  test::TempDir dir;
  const std::string ckpt = (dir / "run.ckpt").string();
  NeuralGenerator straight(tinyNet("family:bilinear", 8, 8));
  const auto a = NeuralTrainer::make(straight, tinyTraining(6));
  a->run(6);

  NeuralGenerator first(tinyNet("family:bilinear", 8, 8));
  const auto b = NeuralTrainer::make(first, tinyTraining(6));
  b->run(3);
  b->saveCheckpoint(ckpt);
  NeuralGenerator resumed(tinyNet("family:bilinear", 8, 8));
  const auto c = NeuralTrainer::make(resumed, tinyTraining(6));
  c->loadCheckpoint(ckpt);
  EXPECT_EQ(c->step(), 3);
  c->run(6);
  const auto pa = torchNet(straight).mlp->parameters(), pc = torchNet(resumed).mlp->parameters();
  ASSERT_EQ(pa.size(), pc.size());
  for (std::size_t i = 0; i < pa.size(); ++i) EXPECT_TRUE(torch::equal(pa[i], pc[i])) << i;

  // Trained (non-zero last layer) weights survive save/load bit-exactly.
  const std::string model = (dir / "m.nuldnet").string();
  straight.save(model);
  const NeuralGenerator back = NeuralGenerator::load(model);
  const auto pb = torchNet(back).mlp->parameters();
  for (std::size_t i = 0; i < pa.size(); ++i) EXPECT_TRUE(torch::equal(pa[i], pb[i])) << i;
  EXPECT_GT(pa.back().abs().max().item<float>(), 0);

  // A checkpoint made with other settings is refused, naming the file.
  NeuralGenerator other(tinyNet("family:bilinear", 8, 8));
  const auto d = NeuralTrainer::make(other, tinyTraining(7));
  try {
    d->loadCheckpoint(ckpt);
    FAIL();
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find(ckpt), std::string::npos);
  }
}

// Generation of a few sets runs the net by matrix-vector products
// (Net::residuals); it must give LibTorch's forward values up to float
// summation order, on a net whose last layer is not zero.
TEST(NeuralGenerator, FewRowInferenceMatchesLibTorchForward) {
  NeuralGenerator gen(tinyNet("quarterdisc", 50, 40));
  torch::NoGradGuard noGrad;
  torch::manual_seed(4);
  torchNet(gen).mlp->l5->weight.normal_(0, 0.1);
  torchNet(gen).mlp->l5->bias.normal_(0, 0.1);
  for (int rows : {1, 3}) {
    const torch::Tensor v = torch::rand({rows, 2}, torch::kFloat32);
    const torch::Tensor expected = torchNet(gen).mlp->forward(v);
    const torch::Tensor got = torchNet(gen).residuals(v);
    ASSERT_EQ(got.sizes(), expected.sizes());
    const double scale = expected.abs().max().item<double>();
    ASSERT_GT(scale, 0.01);
    EXPECT_LE((got - expected).abs().max().item<double>(), 1e-5 * scale) << rows << " rows";
  }
}

}  // namespace
}  // namespace nuld
