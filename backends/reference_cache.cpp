#include "backends/reference_cache.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "backends/ranks.h"
#include "backends/set_cache.h"
#include "sampler/io/content_hash.h"

namespace nuld {

namespace fs = std::filesystem;

namespace {

// The files renderReference writes into an entry, and nothing else: clear()
// removes only these, never a file it did not write.
bool isReferenceFile(const fs::path &file) {
  const std::string name = file.filename().string();
  return name.starts_with("reference.") ||
         (name.starts_with(".reference.") && name.find(".tmp") != std::string::npos);
}

std::vector<fs::directory_entry> entryDirs(const fs::path &dir) {
  std::vector<fs::directory_entry> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_directory(ec)) out.push_back(*it);
  std::sort(out.begin(), out.end(),
            [](const auto &a, const auto &b) { return a.path() < b.path(); });
  return out;
}

// "k=v k=v ..." -> map (a description's fields).
std::map<std::string, std::string> fields(const std::string &description) {
  std::map<std::string, std::string> out;
  std::istringstream in(description);
  std::string word;
  while (in >> word)
    if (const auto eq = word.find('='); eq != std::string::npos)
      out[word.substr(0, eq)] = word.substr(eq + 1);
  return out;
}

std::size_t count(const std::map<std::string, std::string> &kv, const std::string &key) {
  const auto it = kv.find(key);
  if (it == kv.end()) return 0;
  try {
    return std::stoul(it->second);
  } catch (...) {
    return 0;
  }
}

// The holders of every flock now, by file ("MAJ:MIN:INODE", as /proc/locks
// names it: lines "N: FLOCK ADVISORY WRITE PID MAJ:MIN:INODE ..."), read
// once per listing, so that listing an entry never takes its lock.
std::map<std::string, long> flockHolders() {
  std::map<std::string, long> out;
  std::ifstream locks("/proc/locks");
  std::string line;
  while (std::getline(locks, line)) {
    std::istringstream in(line);
    std::string id, kind, mode, access, where;
    long pid = 0;
    // A waiter's line ("N: -> FLOCK ...") is a process that holds nothing.
    if (in >> id >> kind && kind == "FLOCK" && in >> mode >> access >> pid >> where)
      out[where] = pid;
  }
  return out;
}

// The pid among `holders` holding `file`'s flock; 0 when none or the file is
// missing.
long flockHolder(const std::map<std::string, long> &holders, const fs::path &file) {
  struct stat st;
  if (holders.empty() || ::stat(file.c_str(), &st) != 0) return 0;
  char device[32];
  std::snprintf(device, sizeof device, "%02x:%02x:%llu", major(st.st_dev), minor(st.st_dev),
                static_cast<unsigned long long>(st.st_ino));
  const auto it = holders.find(device);
  return it == holders.end() ? 0 : it->second;
}

}  // namespace

ReferenceCache ReferenceCache::fromEnvironment() {
  if (const char *dir = std::getenv("NULD_REFERENCE_CACHE"); dir && *dir)
    return ReferenceCache(dir);
  return ReferenceCache(SetCache::fromEnvironment().root() / "references");
}

std::string referenceKey(const std::string &description) {
  return ContentHash().add("nuld-reference ").add(description).hex();
}

fs::path ReferenceCache::entry(const std::string &sceneName, const ReferenceSettings &settings,
                               const std::string &description) const {
  const std::string key = referenceKey(description);
  for (const auto &e : entryDirs(referencesDir()))
    if (e.path().filename().string().ends_with("_" + key)) return e.path();
  std::string name = sceneName;
  for (char &c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-') c = '_';
  if (name.size() > 40) name.resize(40);
  const RenderSettings &r = settings.render;
  return referencesDir() /
         (name + "_" + std::to_string(r.width) + "x" + std::to_string(r.height) + "_" +
          toString(r.integrator) + "_" + std::to_string(settings.totalSpp()) + "spp_" + key);
}

std::vector<ReferenceCache::Entry> ReferenceCache::list() const {
  std::vector<Entry> out;
  std::error_code ec;
  const std::map<std::string, long> holders = flockHolders();
  for (const auto &dir : entryDirs(referencesDir())) {
    Entry e;
    e.dir = dir.path();
    // The readable part is SCENE_WxH_INTEGRATOR_SPPspp_KEY: the scene's name
    // is what precedes the last four fields (it may hold '_' itself).
    std::string name = dir.path().filename().string();
    for (int field = 0; field < 4 && name.rfind('_') != std::string::npos; ++field)
      name.resize(name.rfind('_'));
    e.scene = name;
    // The newest of the directory and its files. Not the clock's zero as a
    // start: libstdc++'s file clock counts from 2174, so every real time is
    // below it and the entry would read as made now.
    e.modified = dir.last_write_time(ec);
    for (fs::directory_iterator it(dir.path(), ec), end; !ec && it != end; it.increment(ec)) {
      e.bytes += it->is_regular_file(ec) ? it->file_size(ec) : 0;
      e.modified = std::max(e.modified, it->last_write_time(ec));
    }
    // An entry whose state cannot be read is listed with what is known.
    try {
      const ReferenceState state = readReferenceState(dir.path() / "reference.state");
      e.description = state.description;
      e.passesDone = state.passesDone;
      e.seconds = state.seconds;
    } catch (const std::runtime_error &) {
    }
    const auto f = fields(e.description);
    const auto get = [&](const char *k) { return f.count(k) ? f.at(k) : std::string("?"); };
    e.resolution = get("res");
    e.integrator = get("integrator");
    e.backend = get("backend");
    e.spp = count(f, "spp");
    const std::size_t passSpp = count(f, "pass_spp");
    e.passes = passSpp ? e.spp / passSpp : 0;
    e.complete =
        e.passes > 0 && e.passesDone >= e.passes && fs::exists(dir.path() / "reference.exr", ec);
    e.lockedBy = flockHolder(holders, dir.path() / "reference.lock");
    out.push_back(std::move(e));
  }
  return out;
}

std::uintmax_t ReferenceCache::bytes() const {
  std::uintmax_t total = 0;
  std::error_code ec;
  for (const auto &dir : entryDirs(referencesDir()))
    for (fs::directory_iterator it(dir.path(), ec), end; !ec && it != end; it.increment(ec))
      total += it->is_regular_file(ec) ? it->file_size(ec) : 0;
  return total;
}

namespace {

// The key at the end of an entry's name: SCENE_WxH_INTEGRATOR_SPPspp_KEY.
std::string keyOfEntry(const fs::path &dir) {
  const std::string name = dir.filename().string();
  return name.substr(name.rfind('_') + 1);
}

// Removes the reference files of the entry `dir` unless another process
// holds its lock: the lock is taken (without waiting) for the removal, so a
// run that starts meanwhile waits for it and then makes the entry anew.
CacheRemoval removeEntry(const fs::path &dir) {
  CacheRemoval out;
  const fs::path lockFile = dir / "reference.lock";
  std::error_code ec;
  int fd = -1;
  if (fs::exists(lockFile, ec)) {
    fd = ::open(lockFile.c_str(), O_RDWR | O_CLOEXEC);
    if (fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const long pid = flockHolder(flockHolders(), lockFile);
      out.skipped.push_back(
          dir.string() + ": " +
          (pid ? "process " + std::to_string(pid) : std::string("another process")) +
          " is making or reading it");
      ::close(fd);
      return out;
    }
  }
  std::vector<fs::path> files;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec) && isReferenceFile(it->path()) && it->path() != lockFile)
      files.push_back(it->path());
  if (ec) out.failed.push_back(dir.string() + ": cannot list it (" + ec.message() + ")");
  files.push_back(lockFile);  // last: it is held until the others are gone
  for (const fs::path &file : files) {
    if (!fs::exists(file, ec)) continue;
    const std::uintmax_t size = fs::file_size(file, ec);
    if (fs::remove(file, ec)) {
      out.freed += size;
      ++out.removed;
    } else {
      out.failed.push_back(file.string() + ": " + ec.message());
    }
  }
  if (fd >= 0) ::close(fd);
  fs::remove(dir, ec);  // only when nothing else is left in it
  return out;
}

}  // namespace

CacheRemoval ReferenceCache::clear() const { return remove("", ""); }

CacheRemoval ReferenceCache::remove(const std::string &key, const std::string &scene) const {
  CacheRemoval out;
  const bool all = key.empty() && scene.empty();
  for (const Entry &e : list())
    if (all || (!key.empty() && keyOfEntry(e.dir) == key) || (!scene.empty() && e.scene == scene))
      out += removeEntry(e.dir);
  return out;
}

std::vector<std::string> ReferenceCache::verify() const {
  std::vector<std::string> out;
  for (const auto &dir : entryDirs(referencesDir()))
    if (const std::string why = referenceProblem(dir.path()); !why.empty())
      out.push_back(why);  // it names the file
  return out;
}

ReferenceLock::ReferenceLock(const fs::path &dir, const std::function<void()> &waiting) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  const int fd = ::open((dir / "reference.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return;
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {
    fd_ = fd;
    return;
  }
  if (errno == EWOULDBLOCK) {
    if (waiting) waiting();
    int rc;
    while ((rc = ::flock(fd, LOCK_EX)) != 0 && errno == EINTR) {
    }
    if (rc == 0) {
      fd_ = fd;
      return;
    }
  }
  ::close(fd);
}

ReferenceLock::~ReferenceLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the lock
}

CachedReference cachedReference(const Scene &scene, const std::string &sceneName,
                                const ReferenceSettings &settings, const ReferenceCache &cache,
                                const std::function<void(const ReferenceProgress &)> &progress,
                                std::size_t stopAfterPasses) {
  CachedReference out;
  out.description = settings.describe(scene);
  // Rank 0 names the entry (a new one only it creates) and locks it; every
  // rank renders into the same name, the others waiting for rank 0 here.
  const Ranks &ranks = Ranks::world();
  std::optional<ReferenceLock> lock;
  std::string name;
  if (ranks.root()) {
    const fs::path entry = cache.entry(sceneName, settings, out.description);
    // Said on stderr as well as through `progress`: a bar off a terminal
    // (a job's log) draws only tenths of the work, and a wait may be long.
    lock.emplace(entry, [&] {
      std::cerr << "\nnuld: note: another process is making this reference in " << entry.string()
                << "; waiting for it\n";
      if (progress) progress(ReferenceProgress{.waiting = true});
    });
    name = entry.string();
  }
  const std::string dir = ranks.broadcast(name);
  out.dir = dir;
  try {
    out.result = renderReference(scene, sceneName, settings, out.dir, progress, stopAfterPasses,
                                 out.description);
  } catch (const fs::filesystem_error &e) {
    throw std::runtime_error(out.dir.string() +
                             ": cannot write the reference cache here (set NULD_CACHE to a "
                             "writable directory): " +
                             e.code().message());
  }
  out.found = out.result.complete && out.result.passesRun == 0;
  return out;
}

std::vector<std::string> referenceListing(const std::vector<ReferenceCache::Entry> &entries,
                                          fs::file_time_type now) {
  std::vector<std::vector<std::string>> cells;
  for (const ReferenceCache::Entry &e : entries) {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.1f", e.seconds);
    const std::string name = e.dir.filename().string();
    cells.push_back(
        {e.scene, e.resolution, e.integrator, e.spp ? std::to_string(e.spp) : "?", e.backend,
         e.complete ? "complete"
                    : "passes " + std::to_string(e.passesDone) + "/" + std::to_string(e.passes) +
                          (e.lockedBy ? ", pid " + std::to_string(e.lockedBy) + " making it" : ""),
         seconds, humanBytes(e.bytes),
         humanAge(std::chrono::duration_cast<std::chrono::seconds>(now - e.modified)),
         name.substr(name.rfind('_') + 1)});
  }
  return padColumns(
      {"scene", "res", "integrator", "spp", "backend", "state", "render_s", "size", "age", "key"},
      cells, [](std::size_t c) { return c == 3 || c == 6 || c == 7; });
}

}  // namespace nuld
