#include "tools/study/set_cache.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <sstream>

#include "sampler/io/content_hash.h"
#include "sampler/io/pointset_io.h"
#include "sampler/io/pointset_metadata.h"
#include "tools/study/optimized_sets.h"

namespace nuld::study {

namespace fs = std::filesystem;

SetCache SetCache::fromEnvironment() {
  const auto env = [](const char *name) -> std::string {
    const char *v = std::getenv(name);
    return v ? v : "";
  };
  if (const std::string dir = env("NULD_CACHE"); !dir.empty()) return SetCache(dir);
  if (const std::string xdg = env("XDG_CACHE_HOME"); !xdg.empty())
    return SetCache(fs::path(xdg) / "nuld");
  if (const std::string home = env("HOME"); !home.empty())
    return SetCache(fs::path(home) / ".cache" / "nuld");
  return SetCache(fs::temp_directory_path() / "nuld-cache");
}

std::string setCacheKey(const Target &target, const OptimizerSettings &settings) {
  return ContentHash()
      .add("nuld-set-cache ")
      .add(std::to_string(kSetCacheVersion))
      .add(" target ")
      .add(target.contentHash())
      .add(" settings ")
      .add(settings.describe())
      .hex();
}

namespace {

// Every regular file of the sets directory (none when it does not exist
// yet): entries, checkpoints and writers' temporaries.
std::vector<fs::directory_entry> filesIn(const fs::path &dir) {
  std::vector<fs::directory_entry> files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return files;
  for (const auto &e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file(ec)) files.push_back(e);
  return files;
}

// An entry's file: a visible point-set file (temporaries are hidden,
// checkpoints end in .ckpt).
bool isEntry(const fs::directory_entry &e) {
  const std::string name = e.path().filename().string();
  return !name.starts_with(".") && e.path().extension() == ".ptsb";
}

// A settings description without what a nested entry may differ in: N, the
// prefix sizes and the bank term's group size (which follows N).
std::string withoutSize(const std::string &describe) {
  std::istringstream in(describe);
  std::string word, out;
  while (in >> word) {
    if (word.starts_with("n=") || word.starts_with("nested=")) continue;
    if (word.starts_with("union=")) word = word.substr(0, word.find('/'));
    out += (out.empty() ? "" : " ") + word;
  }
  return out;
}

}  // namespace

fs::path SetCache::entry(const Target &target, const OptimizerSettings &settings) const {
  // The key decides; the readable part is the name of whoever made the
  // entry first (a map's file stem may differ under another root).
  const std::string key = setCacheKey(target, settings);
  const std::string suffix = "_n" + std::to_string(settings.n) + "_" + key + ".ptsb";
  for (const auto &e : filesIn(setsDir()))
    if (isEntry(e) && e.path().filename().string().ends_with(suffix)) return e.path();
  std::string slug = shortSpec(target.spec());
  for (char &c : slug)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-') c = '_';
  if (slug.size() > 48) slug.resize(48);
  return setsDir() / (slug + suffix);
}

fs::path SetCache::findNested(const Target &target, const OptimizerSettings &settings,
                              std::size_t spp) const {
  const std::string want = withoutSize(settings.describe()), hash = target.contentHash();
  fs::path best;
  std::size_t bestN = 0;
  for (const auto &e : filesIn(setsDir())) {
    if (!isEntry(e)) continue;
    try {
      const PointSet set = readPointSet(e.path().string());
      if (!findMeta(set, meta::kPrefixes) || set.n < spp || (bestN && set.n >= bestN)) continue;
      if (metaOr(set, meta::kTargetHash, "") != hash) continue;
      if (withoutSize(metaOr(set, meta::kSettings, "")) != want) continue;
      best = e.path();
      bestN = set.n;
    } catch (const std::exception &) {
      // An unreadable entry serves nothing (nuld cache list shows it).
    }
  }
  return best;
}

std::vector<SetCache::Entry> SetCache::list() const {
  std::vector<Entry> out;
  std::error_code ec;
  for (const auto &e : filesIn(setsDir())) {
    if (!isEntry(e)) continue;
    Entry entry{e.path(), e.file_size(ec), "", 0, 0, 0};
    try {
      const PointSet set = readPointSet(e.path().string());
      entry.target = shortSpec(metaOr(set, meta::kTarget, "uniform"));
      entry.n = set.n;
      entry.instances = set.instances();
      entry.optimizeSeconds = std::stod(metaOr(set, meta::kOptimizeSeconds, "0"));
    } catch (const std::exception &) {
      entry.target = "(unreadable)";
    }
    out.push_back(std::move(entry));
  }
  std::sort(out.begin(), out.end(),
            [](const Entry &a, const Entry &b) { return a.file.filename() < b.file.filename(); });
  return out;
}

std::uintmax_t SetCache::bytes() const {
  std::uintmax_t total = 0;
  std::error_code ec;
  for (const auto &e : filesIn(setsDir())) total += e.file_size(ec);
  return total;
}

std::uintmax_t SetCache::clear() const {
  std::uintmax_t freed = 0;
  std::error_code ec;
  for (const auto &e : filesIn(setsDir())) {
    const std::uintmax_t size = e.file_size(ec);
    if (fs::remove(e.path(), ec)) freed += size;
  }
  return freed;
}

}  // namespace nuld::study
