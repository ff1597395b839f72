// Sampler hot paths. Run: build/tests/bench_sampler [--benchmark_filter=...]
// The soft-loss benchmarks report point-box pairs per second, counting pairs
// skipped by band culling as evaluated (they are: their value is exact).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <vector>

#include "sampler/loss/box_mass.h"
#include "sampler/loss/boxes.h"
#include "sampler/loss/soft_box_loss.h"
#include "sampler/metrics/discrepancy.h"
#include "sampler/metrics/nonuniform_l2.h"
#include "sampler/sequences/lattice.h"
#include "sampler/sequences/pmj02.h"
#include "sampler/sequences/sequence.h"
#include "sampler/sequences/stratified.h"
#include "sampler/sequences/zsobol.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/image_targets.h"

namespace nuld {
namespace {

std::vector<Point2> owenSobol(std::size_t n) {
  const PointSet s = generatePointSet({SequenceKind::Sobol, Scramble::Owen, 1}, n, 1);
  return s.points;
}

// One optimizer epoch: fresh boxes, masses, loss and gradient.
void BM_SoftBoxLoss(benchmark::State &state) {
  const std::size_t n = state.range(0), m = state.range(1);
  const double alpha = double(state.range(2));
  const auto pts = owenSobol(n);
  const UniformTarget uniform;
  std::vector<Box2> boxes(m);
  std::vector<double> masses(m);
  std::vector<Point2> grad(n);
  Rng rng(7);
  sampleBoxes(BoxKind::MultipleCorner, rng, boxes);
  exactBoxMasses(uniform, boxes, masses);
  for (auto _ : state) {
    benchmark::DoNotOptimize(softBoxLoss(pts, boxes, masses, {alpha}, grad));
  }
  state.counters["pairs/s"] =
      benchmark::Counter(double(n) * double(m), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SoftBoxLoss)
    ->Args({2048, 16384, 20})
    ->Args({2048, 16384, 6000})
    ->Args({2048, 32768, 6000})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// grace_latlong.exr as the optimizer's target, found from the build
// directory or the repository; null (and the benchmark skipped) without it.
std::unique_ptr<GridTarget> loadGrace(benchmark::State &state) {
  const char *path = "../shared/assets/envmaps/grace_latlong.exr";
  for (const char *prefix : {"", "../", "../../"})
    if (std::filesystem::exists(std::string(prefix) + path))
      return loadEnvmapTarget(std::string(prefix) + path);
  state.SkipWithError("grace_latlong.exr not found (run from the build directory)");
  return nullptr;
}

// The spherical environment-map instance: points clustered by the target.
void BM_SoftBoxLossEnvmap(benchmark::State &state) {
  const auto target = loadGrace(state);
  if (!target) return;
  const std::size_t n = 2048, m = 16384;
  auto pts = owenSobol(n);
  for (Point2 &p : pts) p = target->invert(p).x;
  std::vector<Box2> boxes(m);
  std::vector<double> masses(m);
  std::vector<Point2> grad(n);
  Rng rng(7);
  const double alpha = double(state.range(0));
  for (auto _ : state) {
    sampleBoxes(BoxKind::MultipleCorner, rng, boxes);
    exactBoxMasses(*target, boxes, masses);
    benchmark::DoNotOptimize(softBoxLoss(pts, boxes, masses, {alpha}, grad));
  }
  state.counters["pairs/s"] =
      benchmark::Counter(double(n) * double(m), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SoftBoxLossEnvmap)
    ->Arg(20)
    ->Arg(600)
    ->Arg(6000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The exact L2asd objective on the map (the sphere-exact preset's): built
// once per bank (the CDF field from the map's own table and the constant
// mass term over its cells), then one evaluation with gradient per instance
// and epoch, at N = 16 and 64 (the bank term's unions: 256).
void BM_ExactObjectiveEnvmapBuild(benchmark::State &state) {
  const auto target = loadGrace(state);
  if (!target) return;
  for (auto _ : state) benchmark::DoNotOptimize(std::make_unique<NonuniformL2asd>(*target));
}
BENCHMARK(BM_ExactObjectiveEnvmapBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ExactObjectiveEnvmap(benchmark::State &state) {
  const auto target = loadGrace(state);
  if (!target) return;
  const NonuniformL2asd objective(*target);
  auto pts = owenSobol(state.range(0));
  for (Point2 &p : pts) p = target->invert(p).x;
  std::vector<Point2> grad(pts.size());
  for (auto _ : state) benchmark::DoNotOptimize(objective.squared(pts, grad));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ExactObjectiveEnvmap)->Arg(16)->Arg(64)->Arg(256);

void BM_BoxSamplingAndExactMass(benchmark::State &state) {
  const std::size_t m = state.range(0);
  const QuarterDiscTarget disc;
  std::vector<Box2> boxes(m);
  std::vector<double> masses(m);
  Rng rng(3);
  for (auto _ : state) {
    sampleBoxes(BoxKind::MultipleCorner, rng, boxes);
    exactBoxMasses(disc, boxes, masses);
    benchmark::DoNotOptimize(masses.data());
  }
}
BENCHMARK(BM_BoxSamplingAndExactMass)->Arg(16384)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same on the 2048-point instance's target: one epoch's boxes and their
// masses from grace_latlong.exr's 4 MB summed-area table (BM_SoftBoxLossEnvmap
// times these too, so its loss alone is the difference).
void BM_BoxSamplingAndExactMassEnvmap(benchmark::State &state) {
  const auto target = loadGrace(state);
  if (!target) return;
  std::vector<Box2> boxes(state.range(0));
  std::vector<double> masses(boxes.size());
  Rng rng(7);
  for (auto _ : state) {
    sampleBoxes(BoxKind::MultipleCorner, rng, boxes);
    exactBoxMasses(*target, boxes, masses);
    benchmark::DoNotOptimize(masses.data());
  }
}
BENCHMARK(BM_BoxSamplingAndExactMassEnvmap)
    ->Arg(16384)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_StarDiscrepancy(benchmark::State &state) {
  const auto pts = owenSobol(state.range(0));
  const QuarterDiscTarget disc;
  const bool nonUniform = state.range(1);
  for (auto _ : state) benchmark::DoNotOptimize(starDiscrepancy(pts, nonUniform ? &disc : nullptr));
}
BENCHMARK(BM_StarDiscrepancy)
    ->Args({4096, 0})
    ->Args({4096, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_L2(benchmark::State &state) {
  const auto pts = owenSobol(state.range(0));
  for (auto _ : state) {
    benchmark::DoNotOptimize(l2StarDiscrepancy(pts));
    benchmark::DoNotOptimize(l2asd(pts));
  }
}
BENCHMARK(BM_L2)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();

// One Owen-scrambled Sobol set of N points with a fresh seed each time: what
// the renderer's sobol backend does for every pixel and dimension pair.
void BM_OwenSobolSet(benchmark::State &state) {
  std::vector<Point2> pts(std::size_t(state.range(0)));
  std::uint64_t seed = 0;
  for (auto _ : state) {
    generateSet({SequenceKind::Sobol, Scramble::Owen, ++seed}, 0, pts);
    benchmark::DoNotOptimize(pts.data());
  }
  state.counters["points_per_second"] = benchmark::Counter(
      double(state.iterations()) * double(pts.size()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_OwenSobolSet)->Arg(4)->Arg(16)->Arg(64)->Arg(256);

// The same for Owen-scrambled Halton (the halton backend), args N and the
// first dimension: its digits are permuted per prefix, at the dimension's
// prime base (2 and 3 at dimension 0, 179 and 181 at dimension 40, a
// path's eighth bounce).
void BM_OwenHaltonSet(benchmark::State &state) {
  std::vector<Point2> pts(std::size_t(state.range(0)));
  const auto firstDim = std::uint32_t(state.range(1));
  std::uint64_t seed = 0;
  for (auto _ : state) {
    generateSet({SequenceKind::Halton, Scramble::Owen, ++seed}, firstDim, pts);
    benchmark::DoNotOptimize(pts.data());
  }
  state.counters["points_per_second"] = benchmark::Counter(
      double(state.iterations()) * double(pts.size()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_OwenHaltonSet)->Args({16, 0})->Args({16, 40})->Args({64, 40});

// The classic sets the same way, one fresh seed per set (pmj02's base
// sequences are made by an untimed first set, as a renderer's first pixel
// would make them).
template <class Make>
void timeSets(benchmark::State &state, Make make) {
  std::vector<Point2> pts(std::size_t(state.range(0)));
  std::uint64_t seed = 0;
  make(seed, std::span<Point2>(pts));
  for (auto _ : state) {
    make(++seed, std::span<Point2>(pts));
    benchmark::DoNotOptimize(pts.data());
  }
  state.counters["points_per_second"] = benchmark::Counter(
      double(state.iterations()) * double(pts.size()), benchmark::Counter::kIsRate);
}

void BM_StratifiedSet(benchmark::State &state) {
  timeSets(state, [](std::uint64_t s, std::span<Point2> out) { stratifiedSet(s, out); });
}
BENCHMARK(BM_StratifiedSet)->Arg(16)->Arg(256);

void BM_Pmj02Set(benchmark::State &state) {
  timeSets(state, [](std::uint64_t s, std::span<Point2> out) { pmj02Set(s, out); });
}
BENCHMARK(BM_Pmj02Set)->Arg(16)->Arg(256);

void BM_LatticeSet(benchmark::State &state) {
  timeSets(state, [](std::uint64_t s, std::span<Point2> out) { latticeSet(s, out); });
}
BENCHMARK(BM_LatticeSet)->Arg(16)->Arg(256);

// ZSobol's pixels of a 1024 x 1024 image in scan order, one pair, one seed.
void BM_ZSobolSet(benchmark::State &state) {
  timeSets(state, [](std::uint64_t s, std::span<Point2> out) {
    zsobolSet(7, 3, std::uint32_t(s & 1023), std::uint32_t((s >> 10) & 1023), 1024, out);
  });
}
BENCHMARK(BM_ZSobolSet)->Arg(16)->Arg(256);

// One pmj02 base sequence of 2^k points: the cost of a base's first use.
void BM_Pmj02Sequence(benchmark::State &state) {
  std::uint64_t seed = 0;
  for (auto _ : state) benchmark::DoNotOptimize(pmj02Sequence(++seed, int(state.range(0))));
}
BENCHMARK(BM_Pmj02Sequence)->Arg(10)->Arg(16)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace nuld

BENCHMARK_MAIN();
