#include <iostream>

#include "sampler/io/pointset_io.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/target_spec.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"

namespace nuld::cli {

Runner addGenerate(CLI::App &app) {
  struct Options {
    std::string sequence = "sobol", scramble = "owen", target, output;
    std::size_t n = 0, instances = 1;
    std::uint64_t seed = 0;
  };
  auto o = std::make_shared<Options>();
  app.add_option("--sequence", o->sequence, "sobol, halton or random")
      ->check(CLI::IsMember({"sobol", "halton", "random"}))
      ->capture_default_str();
  app.add_option("--scramble", o->scramble, "owen, shift (digital), cp (Cranley-Patterson) or none")
      ->check(CLI::IsMember({"owen", "shift", "cp", "none"}))
      ->capture_default_str();
  app.add_option("--n", o->n, "points per set (any N >= 1)")
      ->required()
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", o->seed, "randomization seed")->capture_default_str();
  app.add_option("--instances", o->instances, "number of independently randomized sets")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--target", o->target, "map the points to this target by inverse CDF (SPEC)");
  app.add_option("-o,--output", o->output, "output file (.ptsb: binary; otherwise text)")
      ->required();
  return [o] {
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
  };
  auto o = std::make_shared<Options>();
  app.add_option("file", o->input, "point-set file of uniform points")->required();
  app.add_option("--target", o->target, "target SPEC to map to by inverse CDF")->required();
  app.add_option("-o,--output", o->output, "output file")->required();
  return [o] {
    PointSet set = readPointSet(o->input);
    if (auto it = set.metadata.find("target"); it != set.metadata.end() && it->second != "uniform")
      throw std::invalid_argument(o->input + ": holds points for target '" + it->second +
                                  "'; expected uniform points to map");
    if (set.metadata.count("generator")) set.metadata["generator"] += "+inverse-cdf";
    mapByInverseCdf(set, *makeTarget(o->target));
    writePointSet(o->output, set);
    std::cerr << "wrote " << set.instances() << " x " << set.n << " points to " << o->output
              << "\n";
    return 0;
  };
}

}  // namespace nuld::cli
