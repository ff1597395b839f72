// The render study's settings and tables: the CSV's columns, the options'
// checks, what a row depends on, and a scene's identity
// (tools/study/render_study.h).

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sampler/io/content_hash.h"
#include "sampler/io/input_file.h"
#include "tools/study/baselines.h"
#include "tools/study/csv_table.h"
#include "tools/study/equal_time.h"
#include "tools/study/render_study.h"

namespace nuld::study {

const std::vector<std::string> &renderStudyColumns() {
  static const std::vector<std::string> columns{"scene",
                                                "backend",
                                                "spp",
                                                "repeats",
                                                "mse",
                                                "mse_stderr",
                                                "relmse",
                                                "relmse_stderr",
                                                "seconds",
                                                "setup_seconds",
                                                "total_seconds",
                                                "equal_time_ratio",
                                                "equal_time_ratio_stderr",
                                                "amortize",
                                                "rays_per_second",
                                                "nonfinite_pixels",
                                                "rejected_samples",
                                                "image",
                                                "error_map"};
  // Later columns at the end, so that readers of the earlier ones by
  // position keep working.
  static const std::vector<std::string> all = [] {
    std::vector<std::string> c = columns;
    c.insert(c.end(), baselineColumns().begin(), baselineColumns().end());
    c.insert(c.end(), screenColumns().begin(), screenColumns().end());
    return c;
  }();
  return all;
}

const std::vector<std::string> &renderStudyDerivedColumns() {
  static const std::vector<std::string> derived = [] {
    std::vector<std::string> d = equalTimeColumns();
    d.insert(d.end(), baselineColumns().begin(), baselineColumns().end());
    // Measured (the first two) or derived, all missing from files written
    // before they existed.
    d.insert(d.end(), screenColumns().begin(), screenColumns().end());
    return d;
  }();
  return derived;
}

const std::vector<std::string> &referenceColumns() {
  static const std::vector<std::string> columns{"scene",       "backend",    "spp",
                                                "resolution",  "integrator", "variance",
                                                "relvariance", "seconds",    "image"};
  return columns;
}

void RenderStudySettings::validate() const {
  if (scenes.empty()) throw std::invalid_argument("study render: no scene given");
  if (backends.empty()) throw std::invalid_argument("--backends: no backend given");
  if (spp.empty()) throw std::invalid_argument("--spp: no sample count given");
  for (std::size_t n : spp)
    if (n == 0) throw std::invalid_argument("--spp: counts must be positive");
  if (repeats == 0) throw std::invalid_argument("--repeats: must be at least 1");
  if (!(amortize >= 1) || !std::isfinite(amortize))
    throw std::invalid_argument("--amortize: expected a number of renders >= 1");
  sets.validate();
  render.check(OverrideNames::options());  // the render settings, as every render checks
  if (out.empty()) throw std::invalid_argument("study render: -o OUTDIR is required");
  for (const auto &b : backends)    // fail now, not after an hour of reference
    parseBackendWord(b);            // the word only: files are read per cell
  for (const auto &scene : scenes)  // every scene file, before the first reference
    if (!isBuiltInScene(scene)) requireInputFile(scene, "the scene file");
}

std::string RenderStudySettings::rowOptions() const {
  const LobeTableSettings lobeDefaults;
  std::ostringstream o;
  o << "repeats=" << repeats << " seed=" << seed << " res="
    << (render.width ? std::to_string(*render.width) + "x" +
                           (render.height ? std::to_string(*render.height) : "aspect")
                     : "scene")
    << " res-scale=" << formatNumber(render.resolutionScale)
    << " integrator=" << (render.integrator ? toString(*render.integrator) : "scene")
    << " max-depth=" << (render.maxDepth ? std::to_string(*render.maxDepth) : "scene")
    << " lobe-mix=" << (render.lobeMix ? formatNumber(*render.lobeMix) : "auto")
    << " lobe-routes=" << toString(render.lobeRouting.value_or(lobeDefaults.routing))
    << " lobe-defensive=" << formatNumber(render.lobeDefensive.value_or(lobeDefaults.defensive))
    << " lobe-bounces=" << render.lobeBounces.value_or(lobeDefaults.bounces)
    << " lobe-choice=" << toString(choices.lobes)
    << " env-importance=" << (choices.importance ? toString(*choices.importance) : "scene")
    << " opt-instances=" << sets.instances << " opt-epochs=" << sets.epochs
    << " opt-lobe-epochs=" << sets.lobeBankEpochs()
    << " opt-objective=" << toString(sets.envObjective)
    << " opt-union-weight=" << formatNumber(sets.unionWeight)
    << (sets.nested ? " opt-nested=on" : "") << " reference-spp=" << reference.spp
    << " reference-pass-spp=" << reference.passSpp << " reference-backend=" << reference.backend;
  return o.str();
}

std::string sceneIdentity(const std::string &scenePath) {
  const std::string name = slug(scenePath);
  if (isBuiltInScene(scenePath)) return name;
  std::ifstream in(scenePath, std::ios::binary);
  if (!in) throw std::runtime_error(scenePath + ": cannot read the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx",
                static_cast<unsigned long long>(hashString(text.str())));
  return name + " scene_hash=" + hash;
}

}  // namespace nuld::study
