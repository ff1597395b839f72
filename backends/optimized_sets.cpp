#include "backends/optimized_sets.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "backends/set_cache.h"
#include "sampler/io/pointset_io.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/optimize/optimizer.h"
#include "sampler/targets/target_spec.h"

namespace nuld {

namespace fs = std::filesystem;

OptimizerSettings optimizerSettings(const Target &target, const OptimizedSetsRequest &r) {
  OptimizerSettings s = presetSettings(r.preset.empty() ? defaultPreset(target) : r.preset, r.n);
  s.instances = r.instances;
  s.seed = r.seed;
  if (r.epochs > 0) s.epochs = r.epochs;
  if (r.objective) s.objective = *r.objective;
  // The bank term couples two instances or more (a preset's too).
  s.unionWeight = s.objective == Objective::ExactL2asd && s.instances > 1 ? r.unionWeight : 0;
  s.nestedSizes = r.nested;
  // Nested prefixes weigh (m / n)^2: each prefix's squared discrepancy, which
  // falls about as 1/m^2, counts about as much as the full set's
  // (tools/experiments/setup_nested_sets.md).
  if (!r.nested.empty()) s.nestedPower = 2;
  // The periodic objective is defined on the torus: points wrap. Its best
  // measured schedule starts higher than the uniform preset's
  // (tools/experiments/graph_generator_log.md has the sweep).
  if (s.objective == Objective::PeriodicL2) {
    s.mapping = Mapping::Toroidal;
    s.lrStart = 1e-2;
    s.lrEnd = 1e-6;
  }
  return s;
}

std::string shortSpec(const std::string &spec) {
  const auto colon = spec.find(':');
  if (colon == std::string::npos || (spec.rfind("envmap:", 0) != 0 && spec.rfind("image:", 0) != 0))
    return spec;
  return spec.substr(0, colon + 1) + fs::path(spec.substr(colon + 1)).stem().string();
}

namespace {

double recordedSeconds(const PointSet &set) {
  const std::string *seconds = findMeta(set, meta::kOptimizeSeconds);
  try {
    return seconds ? std::stod(*seconds) : 0.0;
  } catch (...) {
    return 0.0;
  }
}

}  // namespace

OptimizedSets optimizedSets(const Target &target, const OptimizedSetsRequest &request,
                            const fs::path &path,
                            const std::function<void(int, int, double)> &progress) {
  const OptimizerSettings settings = optimizerSettings(target, request);
  if (const std::optional<PointSet> found = readVerifiedEntry(path)) {
    const PointSet &cached = *found;
    const std::string cachedSettings = metaOr(cached, meta::kSettings, ""),
                      cachedTarget = metaOr(cached, meta::kTarget, "");
    if (cachedSettings != settings.describe() ||
        !followsTarget(cached, target.spec(), target.contentHash()))
      throw std::runtime_error(path.string() + ": cached sets were optimized with '" +
                               cachedSettings + "' for '" + cachedTarget +
                               "', but this study asks for '" + settings.describe() + "' for '" +
                               target.spec() + "' (use another output directory)");
    return {path, recordedSeconds(cached), true};
  }

  const PointSet set = optimizeSets(target, request, path, progress);
  writeOptimizedSets(path, set);
  return {path, recordedSeconds(set), false};
}

PointSet optimizeSets(const Target &target, const OptimizedSetsRequest &request,
                      const fs::path &path, const std::function<void(int, int, double)> &progress) {
  // Setup counts the objective's own set-up too (the exact L2asd's CDF field
  // of the map). Time spent before an interruption is not known; this run's
  // is counted.
  const auto start = std::chrono::steady_clock::now();
  const DirectOptimizer opt(target, optimizerSettings(target, request));
  fs::create_directories(path.parent_path());
  const std::string ckpt = path.string() + ".ckpt";
  OptimizerState state = opt.initialState();
  const ResumableRun run = resumableRun(opt, target.spec(), state, [&](const EpochReport &r) {
    if (progress) progress(r.epoch, r.epochs, r.loss);
  });
  const RunFlags flags{.resume = true};
  // An interrupted render or study continues the set where its checkpoint
  // left it, and says so.
  std::ostringstream resumed;
  resumeRun(run, ckpt, flags, fs::exists(ckpt) ? &resumed : nullptr);
  if (!resumed.str().empty()) std::cerr << "\nnuld: note: sets " << resumed.str();
  driveRun(run, ckpt, flags, nullptr);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  PointSet set = opt.points(state);
  setMeta(set, meta::kOptimizeSeconds, std::to_string(seconds));
  return set;
}

std::vector<SetsJob> makeMissingSets(const Ranks &ranks, const std::vector<SetsJob> &jobs,
                                     const SetsProgress &progress) {
  std::vector<SetsJob> missing;
  for (const SetsJob &job : jobs)
    if (!verifiedEntry(job.file) &&
        std::none_of(missing.begin(), missing.end(),
                     [&](const SetsJob &m) { return m.file == job.file; }))
      missing.push_back(job);
  // A file that another process (a render, a study, a second bank) writes
  // while this one works is taken as found: its sets are not optimized
  // again, nor written over, nor counted as made here.
  std::size_t done = 0;
  std::string written(missing.size(), '0');
  runInRounds(
      ranks, missing.size(),
      [&](std::size_t i) {
        const SetsJob &job = missing[i];
        if (verifiedEntry(job.file)) return std::string();
        return ByteWriter()
            .put(optimizeSets(*job.target, job.request, job.file,
                              [&](int epoch, int epochs, double loss) {
                                if (progress && ranks.root())
                                  progress(done, missing.size(), job, epoch, epochs, loss);
                              }))
            .take();
      },
      [&](std::size_t i, const std::string &bytes) {
        ++done;
        // Found written by another process: this one's checkpoint, rewritten
        // while it worked, is removed all the same.
        if (bytes.empty() || verifiedEntry(missing[i].file)) {
          std::error_code ec;
          fs::remove(missing[i].file.string() + ".ckpt", ec);
          return;
        }
        writeOptimizedSets(missing[i].file, fromBytes<PointSet>(bytes));
        written[i] = '1';
      });
  written = ranks.broadcast(written);  // the sets are on disk before any rank reads them
  std::vector<SetsJob> made;
  for (std::size_t i = 0; i < missing.size(); ++i)
    if (written[i] == '1') made.push_back(missing[i]);
  return made;
}

void writeOptimizedSets(const fs::path &path, const PointSet &sets) {
  writeCacheEntry(path, sets);
  fs::remove(path.string() + ".ckpt");
}

}  // namespace nuld
