// The render study's settings and tables: the CSV's columns, the options'
// checks, what a row depends on, and a scene's identity
// (tools/study/render_study.h).

#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
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
    c.insert(c.end(), robustColumns().begin(), robustColumns().end());
    c.insert(c.end(), flipColumns().begin(), flipColumns().end());
    c.insert(c.end(), timeSpreadColumns().begin(), timeSpreadColumns().end());
    c.push_back("label");  // the row's name (rowLabel): its backend word, or LABEL of LABEL=WORD
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
    d.insert(d.end(), robustColumns().begin(), robustColumns().end());
    d.insert(d.end(), flipColumns().begin(), flipColumns().end());
    d.insert(d.end(), timeSpreadColumns().begin(), timeSpreadColumns().end());
    d.push_back("label");
    return d;
  }();
  return derived;
}

const std::vector<std::string> &referenceColumns() {
  static const std::vector<std::string> columns{
      "scene",   "backend", "spp",          "resolution", "integrator", "variance", "relvariance",
      "seconds", "image",   "made_seconds", "cache",      "key",        "entry"};
  return columns;
}

const std::vector<std::string> &referenceOptionalColumns() {
  static const std::vector<std::string> columns{"variance", "relvariance", "made_seconds",
                                                "cache",    "key",         "entry"};
  return columns;
}

void RenderStudySettings::validate() const {
  if (scenes.empty()) throw std::invalid_argument("study render: no scene given");
  if (backends.empty()) throw std::invalid_argument("--backends: no backend given");
  if (spp.empty()) throw std::invalid_argument("--spp: no sample count given");
  for (std::size_t n : spp)
    if (n == 0) throw std::invalid_argument("--spp: counts must be positive");
  if (repeats == 0) throw std::invalid_argument("--repeats: must be at least 1");
  if (!(budget.targetStderr >= 0) || !std::isfinite(budget.targetStderr))
    throw std::invalid_argument("--target-stderr: expected a number >= 0 (0: fixed repeats)");
  if (budget.targetStderr > 0 && budget.maxRepeats < std::max<std::size_t>(repeats, 2))
    throw std::invalid_argument("--max-repeats: expected at least --repeats (" +
                                std::to_string(repeats) + ") and 2, got " +
                                std::to_string(budget.maxRepeats));
  if (!(budget.seconds >= 0) || !std::isfinite(budget.seconds))
    throw std::invalid_argument("--budget-seconds: expected a number of seconds >= 0 (0: none)");
  if (!(amortize >= 1) || !std::isfinite(amortize))
    throw std::invalid_argument("--amortize: expected a number of renders >= 1");
  sets.validate();
  render.check(OverrideNames::options());  // the render settings, as every render checks
  if (out.empty()) throw std::invalid_argument("study render: -o OUTDIR is required");
  std::set<std::string> labels;
  for (const auto &b : backends) {  // fail now, not after an hour of reference
    parseBackendWord(b);            // the word only: files are read per cell
    // Rows are named by their labels in tables and files.
    if (!labels.insert(slug(rowLabel(b))).second)
      throw std::invalid_argument("--backends: two rows named '" + rowLabel(b) +
                                  "' (label one of them: LABEL=WORD)");
  }
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

}  // namespace nuld::study
