// Neural generator benchmarks (Google Benchmark; not timed tests):
//  - TrainStep/hH_nN_alphaA: one training step, batch 16, 8192 boxes per set,
//    on the quarter-disc, at sigmoid scale A; counters split the step into
//    the network (forward, backward, Adam) and the soft box loss kernel (with
//    the box masses). The kernel's cost falls as alpha rises (a sharper
//    sigmoid reaches fewer point-box pairs within the cutoff), so a training
//    run, whose alpha ramps 20 -> 2000, averages between the two rows.
//  - Inference/hH_nN: one set from one offset z (batch 1), and per set when
//    64 sets are generated in one batched call.

#include <benchmark/benchmark.h>

#include "sampler/neural/neural_trainer.h"

namespace nuld {
namespace {

NeuralSettings net(int hidden, std::size_t n) {
  NeuralSettings s;
  s.n = n;
  s.hidden = hidden;
  s.family = "quarterdisc";
  return s;
}

void TrainStep(benchmark::State &state) {
  NeuralGenerator gen(net(int(state.range(0)), std::size_t(state.range(1))));
  TrainerSettings t;
  t.steps = 1 << 30;
  t.batch = 16;
  t.boxes = 8192;
  t.alphaStart = t.alphaEnd = double(state.range(2));
  const auto trainer = NeuralTrainer::make(gen, t);
  TrainReport last;
  trainer->run(1, [&](const TrainReport &r) { last = r; });  // warm-up
  const TrainReport warm = last;
  int steps = 0;
  for (auto _ : state) {
    trainer->run(trainer->step() + 1, [&](const TrainReport &r) { last = r; });
    ++steps;
  }
  state.counters["mlp_ms"] = 1e3 * (last.mlpSeconds - warm.mlpSeconds) / steps;
  state.counters["loss_ms"] = 1e3 * (last.lossSeconds - warm.lossSeconds) / steps;
}

void Inference(benchmark::State &state) {
  const NeuralGenerator gen(net(int(state.range(0)), std::size_t(state.range(1))));
  const std::size_t sets = std::size_t(state.range(2));
  std::vector<Point2> z(sets, Point2{0.3, 0.7}), out(sets * gen.settings().n);
  for (std::size_t k = 0; k < sets; ++k) z[k] = {0.01 * double(k % 100), 0.5};
  for (auto _ : state) {
    gen.generate(z, {}, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["sets_per_second"] =
      benchmark::Counter(double(sets), benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(TrainStep)
    ->ArgNames({"hidden", "n", "alpha"})
    ->Args({256, 256, 20})
    ->Args({256, 256, 2000})
    ->Args({1024, 2048, 20})
    ->Args({1024, 2048, 2000})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(Inference)
    ->ArgNames({"hidden", "n", "sets"})
    ->Args({256, 2048, 1})
    ->Args({1024, 2048, 1})
    ->Args({256, 2048, 64})
    ->Args({1024, 2048, 64})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace nuld

BENCHMARK_MAIN();
