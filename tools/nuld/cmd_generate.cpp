#include <iostream>

#include "sampler/bluenoise/sliced_ot.h"
#include "sampler/io/pointset_io.h"
#include "sampler/neural/neural_generator.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/target_spec.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"
#include "tools/nuld/progress.h"

namespace nuld::cli {
namespace {

template <class Options>
int generateFromModel(const Options &o) {
  if (!o.target.empty())
    throw std::invalid_argument(
        "generate: --model makes sets for the model's own target; "
        "drop --target");
  const NeuralGenerator gen = NeuralGenerator::load(o.model);
  if (o.n != 0 && o.n != gen.settings().n)
    throw std::invalid_argument("generate: --n " + std::to_string(o.n) + " but " + o.model +
                                " makes sets of " + std::to_string(gen.settings().n));
  std::vector<double> gamma;
  if (!o.gamma.empty())
    gamma = parseNumberList("--gamma " + o.gamma, o.gamma, 0, 64, "numbers in [0, 1]");
  if (gamma.size() != gen.gammaDimension())
    throw std::invalid_argument("generate: " + o.model + " (" + gen.family().spec() + ") needs " +
                                std::to_string(gen.gammaDimension()) + " --gamma values, got " +
                                std::to_string(gamma.size()));
  PointSet set = gen.generateSets(o.instances, o.seed, gamma);
  set.metadata["generator"] = "neural:" + o.model;
  set.metadata["target"] = gen.family().target(gamma)->spec();
  set.metadata["domain"] = toString(gen.domain());
  if (!o.gamma.empty()) set.metadata["gamma"] = o.gamma;
  if (const std::string why = gen.notRandomizedReason(); !why.empty()) {
    set.metadata["offset_range"] = gen.metadata().at("offset_range");
    std::cerr << "note: " << o.model << ": " << why << "\n";
  }
  writePointSet(o.output, set);
  std::cerr << "wrote " << set.instances() << " x " << set.n << " points to " << o.output << "\n";
  return 0;
}

// Sliced optimal transport (sampler/bluenoise/sliced_ot.h): K sets from
// independent uniform starts, transported to the target (sot) or to the
// uniform square and then mapped by the target's inverse CDF (sot-mapped).
template <class Options>
int generateSlicedOt(const Options &o) {
  const bool mapped = o.sequence == "sot-mapped";
  const std::unique_ptr<Target> target = makeTarget(o.target.empty() ? "uniform" : o.target);
  const std::unique_ptr<Target> uniform = makeTarget("uniform");
  const Target &transportTo = mapped ? *uniform : *target;
  const SliceDestinations destinations(transportTo, o.sot, o.n);
  PointSet set;
  set.n = o.n;
  set.points.resize(o.n * o.instances);
  ProgressBar bar("iteration", long(o.instances) * o.sot.iterations, 0, o.quiet);
  for (std::size_t k = 0; k < o.instances; ++k) {
    const std::span<Point2> points = set.instance(k);
    Rng start(o.seed, hash3(0x57A27, k, o.n));
    for (Point2 &p : points) p = {start.uniform(), start.uniform()};
    slicedOtTransport(destinations, o.sot, std::uint32_t(k), points, [&](int it) {
      if (it % 16 == 0 || it == o.sot.iterations)
        bar.update(long(k) * o.sot.iterations + it,
                   "set " + std::to_string(k + 1) + "/" + std::to_string(o.instances));
    });
  }
  bar.finish("");
  set.metadata["generator"] = o.sequence;
  set.metadata["sot"] = o.sot.describe();
  if (!transportTo.isUniform())
    set.metadata["sot_target_samples"] = std::to_string(o.sot.samplesFor(o.n));
  set.metadata["target"] = transportTo.spec();
  set.metadata["domain"] = toString(transportTo.domain());
  if (mapped && !o.target.empty()) mapByInverseCdf(set, *target);
  writePointSet(o.output, set);
  std::cerr << "wrote " << set.instances() << " x " << set.n << " points to " << o.output << "\n";
  return 0;
}

}  // namespace

Runner addGenerate(CLI::App &app) {
  struct Options {
    std::string sequence = "sobol", scramble = "owen", target, output, model, gamma;
    std::size_t n = 0, instances = 1;
    std::uint64_t seed = 0;
    SlicedOtSettings sot;
    bool quiet = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("--sequence", o->sequence,
                 "sobol, halton, random, sot (sliced optimal transport to --target) or "
                 "sot-mapped (sliced optimal transport to the uniform square, then --target's "
                 "inverse CDF)")
      ->check(CLI::IsMember({"sobol", "halton", "random", "sot", "sot-mapped"}))
      ->capture_default_str();
  app.add_option("--iterations", o->sot.iterations, "sot: iterations")->capture_default_str();
  app.add_option("--slices", o->sot.slices, "sot: directions per iteration")->capture_default_str();
  app.add_option("--step", o->sot.step, "sot: fraction of the averaged displacement applied")
      ->capture_default_str();
  app.add_option("--target-samples", o->sot.targetSamples,
                 "sot: size of the target's stratified sample (default max(64 N, 16384); the "
                 "uniform target's projections are exact)");
  app.add_flag("-q,--quiet", o->quiet, "no progress bar");
  app.add_option("--scramble", o->scramble, "owen, shift (digital), cp (Cranley-Patterson) or none")
      ->check(CLI::IsMember({"owen", "shift", "cp", "none"}))
      ->capture_default_str();
  app.add_option("--n", o->n, "points per set (any N >= 1; required unless --model)")
      ->check(CLI::PositiveNumber);
  app.add_option("--model", o->model,
                 "a trained neural generator: K sets for K random offsets z (from --seed)");
  app.add_option("--gamma", o->gamma,
                 "with --model: the family parameter as comma-separated numbers in [0, 1]");
  app.add_option("--seed", o->seed, "randomization seed")->capture_default_str();
  app.add_option("--instances", o->instances, "number of independently randomized sets")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--target", o->target, "map the points to this target by inverse CDF (SPEC)");
  app.add_option("-o,--output", o->output, "output file (.ptsb: binary; otherwise text)")
      ->required();
  return [o, &app] {
    const bool sot = o->sequence.rfind("sot", 0) == 0;
    if (!sot)
      for (const char *sotOnly : {"--iterations", "--slices", "--step", "--target-samples"})
        if (app.count(sotOnly))
          throw std::invalid_argument(std::string("generate: ") + sotOnly +
                                      " applies to --sequence sot or sot-mapped only");
    if (!o->model.empty()) return generateFromModel(*o);
    if (o->n == 0) throw std::invalid_argument("generate: --n is required (or --model)");
    if (sot) {
      if (app.count("--scramble"))
        throw std::invalid_argument("generate: --scramble does not apply to --sequence " +
                                    o->sequence + " (its sets start from independent points)");
      o->sot.seed = o->seed;
      return generateSlicedOt(*o);
    }
    SequenceOptions so{parseSequenceKind(o->sequence), parseScramble(o->scramble), o->seed};
    if (so.kind != SequenceKind::Random && so.scramble == Scramble::None && o->instances > 1)
      std::cerr << "nuld: warning: unscrambled " << o->sequence << " gives identical instances\n";
    PointSet set = generatePointSet(so, o->n, o->instances);
    if (!o->target.empty()) mapByInverseCdf(set, *makeTarget(o->target));
    writePointSet(o->output, set);
    std::cerr << "wrote " << set.instances() << " x " << set.n << " points to " << o->output
              << "\n";
    return 0;
  };
}

Runner addMap(CLI::App &app) {
  struct Options {
    std::string input, target, output;
    std::size_t shifts = 0;
    std::uint64_t seed = 0;
  };
  auto o = std::make_shared<Options>();
  app.add_option("file", o->input, "point-set file of uniform points")->required();
  app.add_option("--target", o->target, "target SPEC to map to by inverse CDF")->required();
  app.add_option("--shifts", o->shifts,
                 "randomize first: K Cranley-Patterson shifts (from --seed) of every input set, "
                 "so the output has K times its instances (for sets optimized with --objective "
                 "l2per, whose quality no shift changes)")
      ->check(CLI::Range(1, 1 << 20));
  app.add_option("--seed", o->seed, "seed of the shifts")->capture_default_str();
  app.add_option("-o,--output", o->output, "output file")->required();
  return [o, &app] {
    if (app.count("--seed") && o->shifts == 0)
      throw std::invalid_argument("map: --seed draws the --shifts; give --shifts K");
    PointSet set = readPointSet(o->input);
    if (auto it = set.metadata.find("target"); it != set.metadata.end() && it->second != "uniform")
      throw std::invalid_argument(o->input + ": holds points for target '" + it->second +
                                  "'; expected uniform points to map");
    if (o->shifts > 0) {
      // Shift s of set k moves every point by the same offset modulo 1.
      PointSet shifted;
      shifted.n = set.n;
      shifted.metadata = set.metadata;
      Rng rng(o->seed, 0xC9);
      for (std::size_t k = 0; k < set.instances(); ++k)
        for (std::size_t s = 0; s < o->shifts; ++s) {
          const Point2 z{rng.uniform(), rng.uniform()};
          for (const Point2 &p : set.instance(k))
            shifted.points.push_back({wrapUnit(p.x + z.x), wrapUnit(p.y + z.y)});
        }
      shifted.metadata["randomization"] =
          "cranley-patterson x" + std::to_string(o->shifts) + " seed " + std::to_string(o->seed);
      set = std::move(shifted);
    }
    if (set.metadata.count("generator")) set.metadata["generator"] += "+inverse-cdf";
    mapByInverseCdf(set, *makeTarget(o->target));
    writePointSet(o->output, set);
    std::cerr << "wrote " << set.instances() << " x " << set.n << " points to " << o->output
              << "\n";
    return 0;
  };
}

}  // namespace nuld::cli
