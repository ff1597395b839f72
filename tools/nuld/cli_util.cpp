#include "tools/nuld/cli_util.h"

#include <cstdio>
#include <stdexcept>

#include "sampler/targets/basic_targets.h"
#include "sampler/targets/target_spec.h"

namespace nuld::cli {

std::unique_ptr<Target> targetFor(const std::string &spec, const PointSet &set) {
  if (!spec.empty()) return makeTarget(spec);
  if (auto it = set.metadata.find("target"); it != set.metadata.end())
    return makeTarget(it->second);
  return std::make_unique<UniformTarget>();
}

void mapByInverseCdf(PointSet &set, const Target &target) {
  if (!target.hasInverse())
    throw std::invalid_argument("target '" + target.spec() +
                                "' has no inverse CDF to map points with");
  for (Point2 &p : set.points) p = target.invert(p).x;
  set.metadata["target"] = target.spec();
  set.metadata["domain"] = toString(target.domain());
  set.metadata["mapping"] = "inverse-cdf";
}

std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace nuld::cli
