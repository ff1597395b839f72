#pragma once
// Directly optimized sets (Algorithm 1) for a study, made once and cached:
// the render study needs K instances of N = spp points for each scene's
// environment map (and for the uniform target) at every spp it renders, and a
// rerun of the study should not pay for them again. The optimization itself
// checkpoints beside the cache file, so an interrupted study resumes it.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "backends/ranks.h"
#include "sampler/io/content_hash.h"
#include "sampler/optimize/optimizer.h"
#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

// The studies' weight of the bank term (optimizer.h, unionWeight) for lobe
// banks: a glossy lobe's 64 sets of 16 stay on their table by a chi-square
// test of their union from weight 3 on (p 0.06-0.59 over three seeds; 2 fails
// one), and a broad lobe keeps most of each set's own gain only up to 3
// (tools/experiments/lobe_banks_log.md §5, §8).
inline constexpr double kBankUnionWeight = 3;

struct OptimizedSetsRequest {
  std::size_t n = 16;
  std::size_t instances = 16;
  std::string preset;  // empty: by the target (uniform, nonuniform, sphere)
  int epochs = 0;      // 0: the preset's
  std::uint64_t seed = 1;
  std::optional<Objective> objective;  // nullopt: the preset's
  double unionWeight = 0;              // the bank term (optimizer.h); l2asd only
  std::vector<std::size_t> nested;     // prefix sizes below n (OptimizerSettings::nestedSizes)
};

// The optimizer settings a request stands for: the target's preset, with
// the request's overrides (the periodic objective implies toroidal mapping).
OptimizerSettings optimizerSettings(const Target &target, const OptimizedSetsRequest &request);

// envmap:/long/path/grace_latlong.exr -> envmap:grace_latlong, for names.
std::string shortSpec(const std::string &spec);

struct OptimizedSets {
  std::filesystem::path file;  // a point-set file, metadata "target" = target.spec()
  double seconds = 0;          // optimization time (recorded in the file, also when cached)
  bool cached = false;
};

// Returns the file `path`, optimizing it first unless it exists with the same
// settings for the same target (by spec or content hash); a file made
// otherwise is refused (naming it).
// `progress(epoch, epochs, loss)` is called during the optimization.
OptimizedSets optimizedSets(const Target &target, const OptimizedSetsRequest &request,
                            const std::filesystem::path &path,
                            const std::function<void(int, int, double)> &progress = {});

// The two halves of making the file, for a job of several ranks (ranks.h)
// where one rank optimizes and rank 0 writes: optimizeSets runs the
// optimization, resuming and keeping up to date the checkpoint `path`.ckpt,
// and returns the sets with their optimization time in the metadata;
// writeOptimizedSets writes them to `path` and removes the checkpoint.
PointSet optimizeSets(const Target &target, const OptimizedSetsRequest &request,
                      const std::filesystem::path &path,
                      const std::function<void(int, int, double)> &progress = {});
void writeOptimizedSets(const std::filesystem::path &path, const PointSet &sets);

// One cache file a study needs: sets for `target` made with `request`.
struct SetsJob {
  const Target *target = nullptr;
  OptimizedSetsRequest request;
  std::filesystem::path file;
  std::string label;  // for progress
};

// Makes every job's file that does not exist yet, once per file, over the
// ranks of the job (ranks.h): one optimization per rank and round, rank 0
// writing the files; every rank returns once they are all on disk, with the
// jobs this call wrote (a file another process writes meanwhile is found,
// not made again). `progress(done, total, job, epoch, epochs, loss)` follows
// rank 0's own optimizations (`done` of `total` made before it).
using SetsProgress = std::function<void(std::size_t done, std::size_t total, const SetsJob &job,
                                        int epoch, int epochs, double loss)>;
std::vector<SetsJob> makeMissingSets(const Ranks &ranks, const std::vector<SetsJob> &jobs,
                                     const SetsProgress &progress = {});

}  // namespace nuld
