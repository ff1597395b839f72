#pragma once
// The cache of optimized sets that every command shares: the studies,
// `nuld render` and the Python module read and write one directory,
// $NULD_CACHE (else $XDG_CACHE_HOME/nuld, else ~/.cache/nuld).
//
// An entry is keyed by what its sets depend on, never by a path: the
// target's content (Target::contentHash: a map's pixels and pixel weight, a
// lobe table's material and view bin), the optimizer's settings (N,
// instances, objective, epochs, seed, ...) and the cache's format version.
// The same map under two asset roots or study directories finds the same
// entry; one changed pixel, weighting or setting misses it.
//
// Entries are written atomically (a hidden temporary file renamed over the
// entry), so concurrent writers (MPI ranks, two studies at once) and a
// writer killed mid-write never leave a torn entry: readers see the whole
// file or none. Two writers of the same entry both optimize it (the same
// deterministic sets) and the last rename wins.
//
// An entry proves itself: its file's checksum covers every byte
// (pointset_io.h) and its metadata records the key it was made for
// (meta::kCacheKey), which must be the key its name ends in. Every use of
// an entry checks both (verifiedEntry); one that fails is moved aside to
// NAME.corrupt, named in a note, and made again: it is never served.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "backends/neural_backend.h"
#include "sampler/optimize/optimizer.h"
#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

// Bumped when an entry's content changes meaning for the same key.
// 2: entries record their key and end in a checksum.
inline constexpr int kSetCacheVersion = 2;

// What removing files from a cache did: the bytes freed and files removed,
// the files that could not be removed (each "FILE: why"), and the entries
// another process holds now, skipped (each "DIR: why").
struct CacheRemoval {
  std::uintmax_t freed = 0;
  std::size_t removed = 0;
  std::vector<std::string> failed, skipped;
  CacheRemoval &operator+=(const CacheRemoval &other);
};

class SetCache {
 public:
  // The directory's entries live in DIR/sets (created on the first write).
  explicit SetCache(std::filesystem::path root) : root_(std::move(root)) {}
  // $NULD_CACHE, else $XDG_CACHE_HOME/nuld, else $HOME/.cache/nuld.
  static SetCache fromEnvironment();

  const std::filesystem::path &root() const { return root_; }
  std::filesystem::path setsDir() const { return root_ / "sets"; }

  // The entry for sets of `target` made with `settings`: the file holding
  // its key if there is one (whatever its readable part), else a new name,
  // readable (target and N) and ending in the key.
  std::filesystem::path entry(const Target &target, const OptimizerSettings &settings) const;
  // The entry for the bank a neural model (its file's checksum) makes for
  // a lobe table at N (backends/neural_backend.h, LobeBankStore).
  std::filesystem::path modelEntry(std::uint64_t modelChecksum, const Target &table,
                                   std::size_t n) const;

  // What an entry's file says of its sets: its metadata (target, settings)
  // and the file's size and modification time.
  struct Entry {
    std::filesystem::path file;
    std::uintmax_t bytes = 0;
    std::string target;  // the recorded spec, whole but for a map's directory
    std::string key;     // setCacheKey, from the file's name ("" if it has none)
    std::size_t n = 0, instances = 0;
    std::optional<std::uint64_t> seed;  // from the recorded settings
    std::optional<int> epochs;
    // A neural model's lobe bank (modelEntry) rather than optimized sets,
    // and then the model's checksum in hex ("?" for a bank saved before it
    // was recorded).
    bool neural = false;
    std::string model;
    std::string prefixes;    // a nested bank's prefix sizes, "4,16" ("" when not nested)
    double unionWeight = 0;  // the bank term's weight (0: off)
    double optimizeSeconds = 0;
    std::filesystem::file_time_type modified{};
  };
  // The entry of one file (in this cache or not); an unreadable file has
  // target "(unreadable)" and n = 0.
  static Entry describe(const std::filesystem::path &file);
  // A nested entry (metadata `prefixes`) for `target` made with `settings`
  // but for N and the prefix sizes, of at least `spp` points: it serves a
  // render or estimate of `spp` samples by prefixes. The smallest such; an
  // empty path when there is none.
  std::filesystem::path findNested(const Target &target, const OptimizerSettings &settings,
                                   std::size_t spp) const;

  // Complete entries in name order (not temporary files or checkpoints); an
  // unreadable file is listed with n = 0.
  std::vector<Entry> list() const;
  // Checkpoints of sets being made, or left by an interrupted run (the same
  // command continues them; clear() removes them), in name order: the
  // file, its size and modification time.
  struct Checkpoint {
    std::filesystem::path file;
    std::uintmax_t bytes = 0;
    std::filesystem::file_time_type modified{};
  };
  std::vector<Checkpoint> checkpoints() const;
  // Bytes of everything under the cache's sets directory (checkpoints and
  // temporaries included).
  std::uintmax_t bytes() const;
  // Removes every entry, checkpoint, quarantined entry and writer's
  // temporary file (never another file of the directory).
  CacheRemoval clear() const;
  // Removes the entry whose key is `key` (16 hex digits) and its checkpoint.
  CacheRemoval remove(const std::string &key) const;
  // Every entry checked as a use checks it (verifiedEntry, without moving
  // it aside): one line "FILE: why" per entry that would not be served.
  std::vector<std::string> verify() const;

 private:
  std::filesystem::path root_;
};

// The key of an entry (16 hex digits): target content, settings, version.
std::string setCacheKey(const Target &target, const OptimizerSettings &settings);

// Why the entry `file` would not be served ("" when it would): it does not
// read (its checksum included), or its recorded key (meta::kCacheKey) is not
// the key its name ends in.
std::string entryProblem(const std::filesystem::path &file);
// The sets of the entry `file`, proved (entryProblem). One with a problem
// is moved aside to FILE.corrupt (replacing an earlier one) with a note on
// stderr naming it, so that it is made again; none then, and when there is
// no file. An entry that cannot be moved aside is an error naming it.
std::optional<PointSet> readVerifiedEntry(const std::filesystem::path &file);
// Whether readVerifiedEntry finds sets to serve.
bool verifiedEntry(const std::filesystem::path &file);
// An entry's sets with the key its name ends in recorded (meta::kCacheKey),
// written atomically and synced (writePointSet).
void writeCacheEntry(const std::filesystem::path &file, PointSet sets);

// The set cache as the renderer's store of neural lobe banks: each bank an
// entry (SetCache::modelEntry) with its serving verdict in its metadata, in
// the cache the environment names when the bank is asked for
// (SetCache::fromEnvironment), so that NULD_CACHE set later still counts.
// An entry that cannot be read is made again; one that cannot be written is
// warned about once and the bank used anyway.
class SetCacheLobeBankStore final : public LobeBankStore {
 public:
  std::optional<LobeBank> load(std::uint64_t model, const Target &table,
                               std::size_t n) const override;
  void save(std::uint64_t model, const Target &table, std::size_t n,
            const LobeBank &bank) const override;
};

// The listing of entries that nuld cache list and nuld bank print: a header
// and one line per row, columns padded to their widest cell; `lead` columns
// (a command's own, such as bank's spp and pair) come first, then n,
// instances, seed, epochs, optimization seconds, size, age (from `now`),
// kind (optimized, or neural and the model's checksum), nesting, the bank
// term's weight, key and the whole target last, never cut. Rows of the same target that differ in
// any setting differ in their key.
struct SetListingRow {
  std::vector<std::string> lead;
  SetCache::Entry entry;
};
std::vector<std::string> setListing(
    const std::vector<std::string> &leadHeaders, const std::vector<SetListingRow> &rows,
    std::filesystem::file_time_type now = std::filesystem::file_time_type::clock::now());

// A header and one line per row of `cells` (as many cells as headers),
// every column but the last padded to its widest cell: numbers (column c
// with numeric(c)) aligned right, text left. The cache listings' layout.
std::vector<std::string> padColumns(const std::vector<std::string> &headers,
                                    const std::vector<std::vector<std::string>> &cells,
                                    const std::function<bool(std::size_t)> &numeric);

// 1.5 KiB, 3 MiB, ...
std::string humanBytes(std::uintmax_t bytes);
// An age for reading: 42s, 7m, 5h, 3d.
std::string humanAge(std::chrono::seconds age);

}  // namespace nuld
