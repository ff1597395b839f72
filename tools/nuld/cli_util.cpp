#include "tools/nuld/cli_util.h"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <regex>
#include <stdexcept>

#include "sampler/io/pointset_metadata.h"
#include "sampler/targets/basic_targets.h"
#include "sampler/targets/target_spec.h"

namespace nuld::cli {

std::unique_ptr<Target> targetFor(const std::string &spec, const PointSet &set) {
  if (!spec.empty()) return makeTarget(spec);
  if (const std::string *target = findMeta(set, meta::kTarget)) return makeTarget(*target);
  return std::make_unique<UniformTarget>();
}

void mapByInverseCdf(PointSet &set, const Target &target) {
  if (!target.hasInverse())
    throw std::invalid_argument("target '" + target.spec() +
                                "' has no inverse CDF to map points with");
  for (Point2 &p : set.points) p = target.invert(p).x;
  setMeta(set, meta::kTarget, target.spec());
  setMeta(set, meta::kDomain, toString(target.domain()));
  setMeta(set, meta::kMapping, std::string(meta::kInverseCdf));
}

Resolution parseResolution(const std::string &text) {
  static const std::regex re(R"((\d{1,9})(?:x(\d{1,9}))?)");
  std::smatch m;
  if (!std::regex_match(text, m, re))
    throw std::invalid_argument("--res '" + text + "': expected W or WxH, e.g. 512 or 640x480");
  Resolution r;
  r.width = std::stoi(m[1]);
  r.height = m[2].matched ? std::stoi(m[2]) : r.width;
  if (r.width < 1 || r.height < 1 || r.width > 32768 || r.height > 32768)
    throw std::invalid_argument("--res '" + text + "': each side must be in [1, 32768]");
  return r;
}

void addRunFlags(CLI::App &app, RunFlags &flags, const std::string &unit,
                 const std::string &alsoDoes) {
  app.add_option("--checkpoint-every", flags.checkpointEvery,
                 unit + "s between checkpoints" + alsoDoes + " (default: about every 5 %)")
      ->check(CLI::PositiveNumber);
  app.add_flag("--resume", flags.resume, "continue from OUTPUT.ckpt if it exists");
  app.add_option("--stop-after", flags.stopAfter, "stop (with a checkpoint) after this " + unit)
      ->check(CLI::NonNegativeNumber);
  app.add_flag("-q,--quiet", flags.quiet, "no progress bar or messages (results still print)");
}

std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace nuld::cli
