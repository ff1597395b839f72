#pragma once
// The cache of reference renders that every study, `nuld render --reference`
// and MPI job shares: $NULD_REFERENCE_CACHE, else DIR/references beside the
// set cache's DIR/sets (set_cache.h: $NULD_CACHE, else
// $XDG_CACHE_HOME/nuld, else ~/.cache/nuld). The variable of its own lets
// experiments start each run with an empty set cache and still share
// references.
//
// A reference is keyed by its description (ReferenceSettings::describe):
// the scene's content (renderer/scene.h, sceneContentKey: meshes, materials,
// map texels, camera, lobe choice), integrator, depth, resolution, spp,
// pass size, backend, seed and the renderer's revision. Paths, study folders
// and backend lists are not part of it, so a second study of the same scene
// and settings renders no reference, and one changed pixel of a map renders
// a new one.
//
// An entry is a directory named SCENE_WxH_INTEGRATOR_SPPspp_KEY holding the
// files renderReference writes: while in progress the partial sums and the
// state, which any later run resumes pass by pass; when complete the
// reference and its two halves. Every file is written atomically, so a run
// killed mid-write leaves the last whole pass. A run holds the entry's
// advisory lock (ReferenceLock) while it reads or makes it, so a second run
// of the same reference (two studies, two jobs of an array on a shared
// cache) waits, saying so on stderr and through its progress, and then
// finds the first run's reference, or resumes its passes if that run died:
// the system releases a dead process's lock.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "backends/reference_render.h"
#include "backends/set_cache.h"

namespace nuld {

class ReferenceCache {
 public:
  // The entries live in `dir` (created on the first write).
  explicit ReferenceCache(std::filesystem::path dir) : dir_(std::move(dir)) {}
  // $NULD_REFERENCE_CACHE, else the set cache's root (SetCache::
  // fromEnvironment) / references.
  static ReferenceCache fromEnvironment();

  const std::filesystem::path &referencesDir() const { return dir_; }

  // The directory of the reference `description` names: the existing one
  // ending in its key (whatever its readable part), else a new name made of
  // `sceneName`, the settings and the key.
  std::filesystem::path entry(const std::string &sceneName, const ReferenceSettings &settings,
                              const std::string &description) const;

  struct Entry {
    std::filesystem::path dir;
    std::uintmax_t bytes = 0;
    std::string description;  // "" when the state cannot be read
    std::string scene;        // the readable part of the directory's name
    std::string resolution, integrator, backend;
    std::size_t spp = 0, passesDone = 0, passes = 0;
    bool complete = false;
    // The process holding the entry's lock now (a run making it, or reading
    // it for a moment), from /proc/locks: 0 when none, or when the system
    // does not say (another host's lock on a network file system).
    long lockedBy = 0;
    double seconds = 0;  // render time of its passes so far, over every run
    std::filesystem::file_time_type modified{};
  };
  // Entries in name order, complete and in progress.
  std::vector<Entry> list() const;
  // Bytes of everything under the references directory.
  std::uintmax_t bytes() const;
  // Removes every entry (only the files references are made of) that no
  // other process holds: an entry whose lock another process holds (a run
  // making or reading it) is skipped and named, never removed under it.
  CacheRemoval clear() const;
  // The same for the entries whose key is `key`, or whose scene (the
  // readable part of its name) is `scene`.
  CacheRemoval remove(const std::string &key, const std::string &scene = "") const;
  // One line "DIR: why" per entry that would not be used
  // (referenceProblem), in progress or complete.
  std::vector<std::string> verify() const;

 private:
  std::filesystem::path dir_;
};

// The advisory lock of an entry: DIR/reference.lock (created with DIR),
// held from construction to destruction by flock(2). `waiting` is called
// once, before blocking, when another process holds it. Where the lock file
// cannot be made or locked (a read-only cache, a file system without
// locks) the object holds nothing and the caller goes on unlocked, as every
// file it writes is still written atomically.
class ReferenceLock {
 public:
  ReferenceLock(const std::filesystem::path &dir, const std::function<void()> &waiting = {});
  ~ReferenceLock();
  ReferenceLock(const ReferenceLock &) = delete;
  ReferenceLock &operator=(const ReferenceLock &) = delete;
  bool held() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

// The key of a description: 16 hex digits.
std::string referenceKey(const std::string &description);

struct CachedReference {
  ReferenceResult result;
  std::filesystem::path dir;  // the cache entry
  std::string description;
  // Complete in the cache before this call: no pass was rendered, and a
  // study counts 0 s for it.
  bool found = false;
};

// Finds the reference in `cache`, or renders (or resumes) it there
// (renderReference's passes, progress and stopAfterPasses; under MPI every
// rank renders passes and rank 0 writes the entry). Rank 0 holds the
// entry's ReferenceLock throughout; while another process holds it,
// `progress` is told so (ReferenceProgress::waiting).
CachedReference cachedReference(const Scene &scene, const std::string &sceneName,
                                const ReferenceSettings &settings, const ReferenceCache &cache,
                                const std::function<void(const ReferenceProgress &)> &progress = {},
                                std::size_t stopAfterPasses = 0);

// The listing `nuld cache list` prints: a header and one line per entry
// (scene, resolution, integrator, spp, state, seconds, size, age, key); the
// state of an entry in progress names the process making it, if any.
std::vector<std::string> referenceListing(
    const std::vector<ReferenceCache::Entry> &entries,
    std::filesystem::file_time_type now = std::filesystem::file_time_type::clock::now());

}  // namespace nuld
