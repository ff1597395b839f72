#pragma once
// The metadata keys of point-set files (pointset_io.h), in one list, and
// typed access to their values. The spellings are the files' format: a key
// renamed here would leave older files unread.

#include <string>
#include <string_view>

#include "sampler/point.h"

namespace nuld {
namespace meta {

// The text format's header, derived from the data (not kept in
// PointSet::metadata: reading drops them).
inline constexpr std::string_view kFormat = "nuld-pointset";  // "1"
inline constexpr std::string_view kN = "n";
inline constexpr std::string_view kInstances = "instances";

// What the points follow: a target SPEC ("uniform" when absent), its domain,
// and how uniform points were carried to it.
inline constexpr std::string_view kTarget = "target";
// Target::contentHash of the target: matches the set to the same density
// under another path (target_spec.h, followsTarget).
inline constexpr std::string_view kTargetHash = "target_hash";
inline constexpr std::string_view kDomain = "domain";
inline constexpr std::string_view kMapping = "mapping";
inline constexpr std::string_view kInverseCdf = "inverse-cdf";  // kMapping's value
// The neural generator's gamma ("a,b,...") and, for a diagnostic model, its
// offset range.
inline constexpr std::string_view kGamma = "gamma";
inline constexpr std::string_view kOffsetRange = "offset_range";

// How the points were made: the generator (a sequence kind, "optimized",
// "neural:MODEL", a blue-noise method; "+inverse-cdf" when mapped later),
// sequences' scrambling and seed, Cranley-Patterson shifts added afterwards.
inline constexpr std::string_view kGenerator = "generator";
inline constexpr std::string_view kScramble = "scramble";
inline constexpr std::string_view kSeed = "seed";
inline constexpr std::string_view kRandomization = "randomization";
// The direct optimizer's settings (OptimizerSettings::describe()), epochs
// run, final metrics (nuld optimize) and wall time (the studies' cache).
inline constexpr std::string_view kSettings = "settings";
// Nested sets (OptimizerSettings::nestedFrom): the prefix sizes optimized as
// sets of their own, "4,8,16,32,64"; a bank with them serves any sample
// count up to its N by prefixes.
inline constexpr std::string_view kPrefixes = "prefixes";
inline constexpr std::string_view kEpochsDone = "epochs_done";
inline constexpr std::string_view kFinalMetrics = "final_metrics";
inline constexpr std::string_view kOptimizeSeconds = "optimize_seconds";
// Blue-noise sets: the method's settings (sliced OT or Gaussian blue noise)
// and the target samples it matched.
inline constexpr std::string_view kSlicedOt = "sot";
inline constexpr std::string_view kGaussianBlueNoise = "gbn";
inline constexpr std::string_view kTargetSamples = "target_samples";
// A generated lobe bank's verdict in its table's serving test, "yes" or "no"
// (the renderer's neural backend; banks kept in the set cache).
inline constexpr std::string_view kServes = "serves";
// The neural model that generated a lobe bank: its file's closing checksum
// (ModelFile::checksum) in hex.
inline constexpr std::string_view kModel = "model";

// The set cache's key an entry was made for (backends/set_cache.h): its
// file's name ends in the same key, and an entry whose two disagree (a file
// copied over another entry) is never served.
inline constexpr std::string_view kCacheKey = "cache_key";

}  // namespace meta

// Sets (or replaces) `key`.
void setMeta(PointSet &set, std::string_view key, std::string value);
// The value of `key`, or nullptr when the set has none.
const std::string *findMeta(const PointSet &set, std::string_view key);
// The value of `key`, or `fallback` when the set has none.
std::string metaOr(const PointSet &set, std::string_view key, std::string_view fallback);

}  // namespace nuld
