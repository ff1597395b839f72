// Materials hot paths: Disney eval / pdf / sample at the supplement's
// instance and at rough glass (its transmission lobe), and building the
// supplement's lobe target. Run: build/tests/bench_materials
#include <benchmark/benchmark.h>

#include <vector>

#include "materials/disney.h"
#include "materials/disney_target.h"
#include "tests/bench/bench_points.h"

namespace nuld {
namespace {

using bench::uniformPoints;

// Rough glass (spec_trans 1, roughness 0.3, IOR 1.5), seen from outside
// as the opaque instance is: its transmission lobe beside the supplement's.
DisneyParams roughGlass() {
  DisneyParams p;
  p.specTrans = 1;
  p.roughness = 0.3;
  return p;
}

// sample() at uniform points, the lobe choice from another point's x.
void sampleBench(benchmark::State &state, const DisneyParams &params) {
  const DisneyBrdf brdf(params);
  const Vec3 wo = supplementWo();
  const auto us = uniformPoints(4096);
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(brdf.sample(wo, us[(k + 7) & 4095].x, us[k & 4095]));
    ++k;
  }
  state.SetItemsProcessed(state.iterations());
}

// eval + pdf at the directions the material samples (both sides for glass).
void evalAndPdfBench(benchmark::State &state, const DisneyParams &params) {
  const DisneyBrdf brdf(params);
  const Vec3 wo = supplementWo();
  std::vector<Vec3> wis;
  for (const Point2 u : uniformPoints(4096))
    if (const auto s = brdf.sampleSquare(wo, u)) wis.push_back(s->wi);
  std::size_t k = 0;
  for (auto _ : state) {
    const Vec3 wi = wis[k++ % wis.size()];
    benchmark::DoNotOptimize(brdf.eval(wo, wi));
    benchmark::DoNotOptimize(brdf.pdf(wo, wi));
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_DisneySample(benchmark::State &state) { sampleBench(state, supplementDisneyParams()); }
BENCHMARK(BM_DisneySample);
void BM_DisneyEvalAndPdf(benchmark::State &state) {
  evalAndPdfBench(state, supplementDisneyParams());
}
BENCHMARK(BM_DisneyEvalAndPdf);
void BM_GlassSample(benchmark::State &state) { sampleBench(state, roughGlass()); }
BENCHMARK(BM_GlassSample);
void BM_GlassEvalAndPdf(benchmark::State &state) { evalAndPdfBench(state, roughGlass()); }
BENCHMARK(BM_GlassEvalAndPdf);

// One lobe target at the default 256 x 128 cells, 4 x 4 evaluations each.
void BM_MakeDisneyTarget(benchmark::State &state) {
  for (auto _ : state)
    benchmark::DoNotOptimize(makeDisneyTarget(supplementDisneyParams(), supplementWo()));
}
BENCHMARK(BM_MakeDisneyTarget)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace nuld

BENCHMARK_MAIN();
