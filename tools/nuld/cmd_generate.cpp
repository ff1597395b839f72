#include <algorithm>
#include <iostream>

#include "sampler/bluenoise/blue_noise_sets.h"
#include "sampler/io/pointset_io.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/neural/neural_generator.h"
#include "sampler/resources.h"
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
  const std::size_t n = o.n != 0 ? o.n : gen.settings().n;
  try {
    gen.checkSize(n);
  } catch (const std::invalid_argument &e) {
    throw std::invalid_argument("generate: --n " + std::to_string(n) + ": " + o.model + ": " +
                                e.what());
  }
  const std::vector<std::size_t> trained = gen.settings().sizesTrained();
  if (std::find(trained.begin(), trained.end(), n) == trained.end() && !o.quiet)
    std::cerr << "note: " << o.model << " was trained at N = "
              << gen.metadata().at(trained.size() > 1 ? "training_n" : "n") << "; sets of " << n
              << " points extrapolate\n";
  std::vector<double> gamma;
  if (!o.gamma.empty())
    gamma = parseNumberList("--gamma " + o.gamma, o.gamma, 0, 64, "numbers in [0, 1]");
  if (gamma.size() != gen.gammaDimension())
    throw std::invalid_argument("generate: " + o.model + " (" + gen.family().spec() + ") needs " +
                                std::to_string(gen.gammaDimension()) + " --gamma values, got " +
                                std::to_string(gamma.size()));
  PointSet set = gen.generateSets(o.instances, o.seed, gamma, n);
  setMeta(set, meta::kGenerator, "neural:" + o.model);
  recordTarget(set, *gen.family().target(gamma));
  setMeta(set, meta::kDomain, toString(gen.domain()));
  if (!o.gamma.empty()) setMeta(set, meta::kGamma, o.gamma);
  if (const std::string why = gen.notRandomizedReason(); !why.empty()) {
    setMeta(set, meta::kOffsetRange, gen.metadata().at("offset_range"));
    std::cerr << "note: " << o.model << ": " << why << "\n";
  }
  writePointSet(o.output, set);
  std::cerr << "wrote " << set.instances() << " x " << set.n << " points to " << o.output << "\n";
  return 0;
}

// The blue-noise baselines (sampler/bluenoise/blue_noise_sets.h): K sets
// from independent uniform starts, optimized for --target or uniformly and
// then mapped (the -mapped names).
template <class Options>
int generateBlueNoise(const Options &o, const CLI::App &app) {
  BlueNoiseRequest request = parseBlueNoiseName(o.sequence);
  request.seed = o.seed;
  const bool sliced = request.method == BlueNoiseMethod::SlicedOt;
  onlyWhen(app, !sliced, {"--sigma", "--boundary"}, "--sequence gbn or gbn-mapped");
  onlyWhen(app, sliced, {"--slices", "--uniform-domain"}, "--sequence sot or sot-mapped");
  // Given values replace each method's own defaults.
  if (app.count("--iterations")) request.sot.iterations = request.gbn.iterations = o.iterations;
  if (app.count("--step")) request.sot.step = request.gbn.step = o.step;
  request.sot.targetSamples = request.gbn.targetSamples = o.targetSamples;
  request.sot.slices = o.slices;
  request.sot.uniformDomain = parseUniformSotDomain(o.uniformDomain);
  request.gbn.sigma = o.sigma;
  request.gbn.boundary = parseEnum<BlueNoiseBoundary>(o.boundary);
  const std::unique_ptr<Target> target = makeTarget(o.target.empty() ? "uniform" : o.target);
  std::unique_ptr<ProgressBar> bar;
  const PointSet set =
      blueNoiseSets(request, *target, o.n, o.instances, [&](long done, long total) {
        if (!bar) bar = std::make_unique<ProgressBar>("iteration", total, 0, o.quiet);
        if (done % 16 == 0 || done == total) bar->update(done, request.name());
      });
  if (bar) bar->finish("");
  writePointSet(o.output, set);
  std::cerr << "wrote " << set.instances() << " x " << set.n << " points to " << o.output << "\n";
  return 0;
}

}  // namespace

Runner addGenerate(CLI::App &app) {
  struct Options {
    std::string sequence = "sobol", scramble = "owen", target, output, model, gamma;
    std::size_t n = 0, instances = 1;
    std::uint64_t seed = kDefaultSeed;
    int iterations = 0, slices = SlicedOtSettings{}.slices;
    double step = 0, sigma = GaussianBlueNoiseSettings{}.sigma;
    std::size_t targetSamples = 0;
    std::string boundary = "bounded", uniformDomain = "disc";
    bool quiet = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option(
         "--sequence", o->sequence,
         "sobol, halton, random, the classic sets stratified (jittered: one point per "
         "cell), pmj02 (progressive multi-jittered (0,2), N <= 65536) and lattice "
         "(rank-1, its best-separated generator), the blue-noise baselines sot (sliced optimal "
         "transport) and gbn (Gaussian blue noise), optimized for --target, or "
         "sot-mapped and gbn-mapped (optimized uniformly, then --target's inverse CDF)")
      ->check(CLI::IsMember([] {
        std::vector<std::string> names = kSequenceKindNames.names();
        for (const std::string &b : kBlueNoiseNames.names()) names.push_back(b);
        return names;
      }()))
      ->capture_default_str();
  app.add_option("--iterations", o->iterations, "sot, gbn: iterations (default 1024, 1000)");
  app.add_option("--step", o->step,
                 "sot: fraction of the averaged displacement applied (default 1); gbn: time step "
                 "(default 0.25, divided by sigma^2 above 1)");
  app.add_option("--slices", o->slices, "sot: directions per iteration")->capture_default_str();
  app.add_option("--sigma", o->sigma, "gbn: kernel width in units of the mean spacing")
      ->capture_default_str();
  app.add_option("--boundary", o->boundary,
                 "gbn, uniform target: bounded (the square's edges attract as the missing "
                 "neighbours beyond them would) or toroidal")
      ->check(oneOf(kBlueNoiseBoundaryNames))
      ->capture_default_str();
  app.add_option("--uniform-domain", o->uniformDomain,
                 "sot, uniform sets (sot on the uniform target, sot-mapped): transported in the "
                 "inscribed disc and mapped to the square area-preservingly, as the authors do, "
                 "or in the square itself")
      ->check(oneOf(kUniformSotDomainNames))
      ->capture_default_str();
  app.add_option("--target-samples", o->targetSamples,
                 "sot, gbn: size of the target's stratified sample (default max(64 N, 16384) "
                 "for sot, max(4 N, 4096) for gbn; the uniform target needs none)");
  app.add_flag("-q,--quiet", o->quiet, "no progress bar");
  app.add_option("--scramble", o->scramble,
                 "owen, shift (digital), cp (Cranley-Patterson), baker (lattice only: cp, "
                 "then the baker's transform) or none; default owen, but cp for lattice (cp "
                 "and shift both shift it on the torus) and none for stratified (its jitter "
                 "is its randomization; nothing else applies); pmj02 takes owen, shift or "
                 "none (one fixed sequence)")
      ->check(oneOf(kScrambleNames));
  app.add_option("--n", o->n,
                 "points per set (any N >= 1; required unless --model; a graph model makes "
                 "any N, its training size by default)")
      ->check(positiveNumber());
  app.add_option("--model", o->model,
                 "a trained neural generator: K sets for K random offsets z (from --seed)");
  app.add_option("--gamma", o->gamma,
                 "with --model: the family parameter as comma-separated numbers in [0, 1]");
  app.add_option("--seed", o->seed, "randomization seed")
      ->capture_default_str()
      ->check(wholeNumber());
  app.add_option("--instances", o->instances, "number of independently randomized sets")
      ->check(positiveNumber())
      ->capture_default_str();
  app.add_option("--target", o->target,
                 targetOptionHelp("map the points to this target by inverse CDF (SPEC)"))
      ->check(targetFamily());
  app.add_option("-o,--output", o->output, "output file (.ptsb: binary; otherwise text)")
      ->required();
  return [o, &app] {
    const bool blueNoise = kBlueNoiseNames.find(o->sequence).has_value();
    onlyWhen(app, blueNoise,
             {"--iterations", "--slices", "--step", "--target-samples", "--sigma", "--boundary",
              "--uniform-domain"},
             "the blue-noise sequences (sot, gbn)");
    if (!o->model.empty()) {
      // A model makes its own sets: a sequence or scrambling would be ignored.
      for (const char *notWithModel : {"--sequence", "--scramble"})
        if (app.count(notWithModel))
          throw std::invalid_argument(std::string("generate: ") + notWithModel +
                                      " does not apply to --model (the model makes its own sets)");
      return generateFromModel(*o);
    }
    onlyWhen(app, false, {"--gamma"}, "--model");
    if (o->n == 0) throw std::invalid_argument("generate: --n is required (or --model)");
    // The sets are held whole before they are written.
    requireMemory(double(o->n) * double(o->instances) * sizeof(Point2),
                  "generate: --n " + std::to_string(o->n) + " x --instances " +
                      std::to_string(o->instances) + " points");
    if (blueNoise) {
      if (app.count("--scramble"))
        throw std::invalid_argument("generate: --scramble does not apply to --sequence " +
                                    o->sequence + " (its sets start from independent points)");
      return generateBlueNoise(*o, app);
    }
    const SequenceKind kind = parseSequenceKind(o->sequence);
    const SequenceOptions so{
        kind, app.count("--scramble") ? parseScramble(o->scramble) : defaultScramble(kind),
        o->seed};
    try {
      checkScramble(so);
    } catch (const std::invalid_argument &e) {
      throw UsageError(std::string("generate: --scramble: ") + e.what());  // exits 2
    }
    if (!randomizesInstances(so) && o->instances > 1)
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
    std::uint64_t seed = kDefaultSeed;
  };
  auto o = std::make_shared<Options>();
  app.add_option("file", o->input, "point-set file of uniform points")->required();
  app.add_option("--target", o->target, targetOptionHelp("target SPEC to map to by inverse CDF"))
      ->required()
      ->check(targetFamily());
  app.add_option("--shifts", o->shifts,
                 "randomize first: K Cranley-Patterson shifts (from --seed) of every input set, "
                 "so the output has K times its instances (for sets optimized with --objective "
                 "l2per, whose quality no shift changes)")
      ->check(wholeNumberIn(1, 1 << 20));
  app.add_option("--seed", o->seed, "seed of the shifts")
      ->capture_default_str()
      ->check(wholeNumber());
  app.add_option("-o,--output", o->output, "output file")->required();
  return [o, &app] {
    if (app.count("--seed") && o->shifts == 0)
      throw std::invalid_argument("map: --seed draws the --shifts; give --shifts K");
    PointSet set = readPointSet(o->input);
    if (const std::string *target = findMeta(set, meta::kTarget); target && *target != "uniform")
      throw std::invalid_argument(o->input + ": holds points for target '" + *target +
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
      setMeta(
          shifted, meta::kRandomization,
          "cranley-patterson x" + std::to_string(o->shifts) + " seed " + std::to_string(o->seed));
      set = std::move(shifted);
    }
    if (const std::string *generator = findMeta(set, meta::kGenerator))
      setMeta(set, meta::kGenerator, *generator + "+" + std::string(meta::kInverseCdf));
    mapByInverseCdf(set, *makeTarget(o->target));
    writePointSet(o->output, set);
    std::cerr << "wrote " << set.instances() << " x " << set.n << " points to " << o->output
              << "\n";
    return 0;
  };
}

}  // namespace nuld::cli
