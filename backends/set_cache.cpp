#include "backends/set_cache.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <optional>
#include <sstream>

#include "backends/optimized_sets.h"
#include "sampler/diagnostics.h"
#include "sampler/io/content_hash.h"
#include "sampler/io/pointset_io.h"
#include "sampler/io/pointset_metadata.h"
#include "sampler/io/round_trip.h"

namespace nuld {

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

// The key at the end of an entry's name: NAME_nN_KEY.ptsb.
std::string keyOf(const fs::path &file) {
  const std::string stem = file.stem().string();
  const auto underscore = stem.rfind('_');
  const std::string key = underscore == std::string::npos ? "" : stem.substr(underscore + 1);
  const bool hex = key.size() == 16 && std::all_of(key.begin(), key.end(), [](char c) {
                     return std::isxdigit(static_cast<unsigned char>(c));
                   });
  return hex ? key : "";
}

// The files the cache writes into its sets directory, and so the only ones
// clear() removes: entries, their checkpoints (ENTRY.ckpt), entries moved
// aside (ENTRY.corrupt) and writers' temporaries (.NAME.tmpPID.ptsb, and
// the checkpoint's).
bool isCacheFile(const fs::directory_entry &e) {
  const std::string name = e.path().filename().string();
  if (isEntry(e)) return !keyOf(e.path()).empty();
  for (const std::string suffix : {".ckpt", ".corrupt"})
    if (name.ends_with(".ptsb" + suffix))
      return !keyOf(fs::path(name.substr(0, name.size() - suffix.size()))).empty();
  return name.starts_with(".") && name.find(".tmp") != std::string::npos;
}

// Removes `file`, counting it into `out`.
void removeInto(const fs::path &file, CacheRemoval &out) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (fs::remove(file, ec)) {
    out.freed += size;
    ++out.removed;
  } else if (ec) {
    out.failed.push_back(file.string() + ": " + ec.message());
  }
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

namespace {

// The key decides; the readable part is the name of whoever made the entry
// first (a map's file stem may differ under another root).
fs::path entryFor(const fs::path &dir, const std::string &prefix, const Target &target,
                  std::size_t n, const std::string &key) {
  const std::string suffix = "_n" + std::to_string(n) + "_" + key + ".ptsb";
  for (const auto &e : filesIn(dir))
    if (isEntry(e) && e.path().filename().string().ends_with(suffix)) return e.path();
  std::string slug = prefix + shortSpec(target.spec());
  for (char &c : slug)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-') c = '_';
  if (slug.size() > 48) slug.resize(48);
  return dir / (slug + suffix);
}

}  // namespace

fs::path SetCache::entry(const Target &target, const OptimizerSettings &settings) const {
  return entryFor(setsDir(), "", target, settings.n, setCacheKey(target, settings));
}

fs::path SetCache::modelEntry(std::uint64_t modelChecksum, const Target &table,
                              std::size_t n) const {
  const std::string key = ContentHash()
                              .add("nuld-lobe-bank ")
                              .add(std::to_string(kSetCacheVersion))
                              .add(" model ")
                              .add(std::to_string(modelChecksum))
                              .add(" table ")
                              .add(table.contentHash())
                              .add(" n ")
                              .add(std::to_string(n))
                              .hex();
  return entryFor(setsDir(), "neural_", table, n, key);
}

std::optional<LobeBank> SetCacheLobeBankStore::load(std::uint64_t model, const Target &table,
                                                    std::size_t n) const {
  const fs::path file = SetCache::fromEnvironment().modelEntry(model, table, n);
  std::optional<PointSet> sets = readVerifiedEntry(file);
  if (!sets) return std::nullopt;
  try {
    LobeBank bank{std::move(*sets), false};
    const std::string serves = metaOr(bank.sets, meta::kServes, "");
    if (bank.sets.n != n || (serves != "yes" && serves != "no")) return std::nullopt;
    bank.serves = serves == "yes";
    return bank;
  } catch (const std::exception &) {
    return std::nullopt;  // made again, and the entry rewritten
  }
}

void SetCacheLobeBankStore::save(std::uint64_t model, const Target &table, std::size_t n,
                                 const LobeBank &bank) const {
  try {
    const fs::path file = SetCache::fromEnvironment().modelEntry(model, table, n);
    PointSet sets = bank.sets;
    setMeta(sets, meta::kTarget, table.spec());
    setMeta(sets, meta::kServes, bank.serves ? "yes" : "no");
    char checksum[24];
    std::snprintf(checksum, sizeof checksum, "%016llx", static_cast<unsigned long long>(model));
    setMeta(sets, meta::kModel, checksum);
    writeCacheEntry(file, std::move(sets));
  } catch (const std::exception &e) {
    static std::once_flag once;
    std::call_once(once, [&] {
      warning(std::string("the set cache: a neural lobe bank was not saved (") + e.what() +
              "); it is made again in the next process");
    });
  }
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
      if (metaOr(set, meta::kCacheKey, "") != keyOf(e.path())) continue;
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

namespace {

// The value of word `name=` in a settings description, if there is one.
std::optional<std::string> settingOf(const std::string &describe, const std::string &name) {
  std::istringstream in(describe);
  std::string word;
  while (in >> word)
    if (word.starts_with(name + "=")) return word.substr(name.size() + 1);
  return std::nullopt;
}

}  // namespace

SetCache::Entry SetCache::describe(const fs::path &file) {
  std::error_code ec;
  Entry entry;
  entry.file = file;
  entry.bytes = fs::file_size(file, ec);
  entry.modified = fs::last_write_time(file, ec);
  entry.key = keyOf(file);
  try {
    const PointSet set = readPointSet(file.string());
    entry.target = shortSpec(metaOr(set, meta::kTarget, "uniform"));
    entry.n = set.n;
    entry.instances = set.instances();
    entry.optimizeSeconds = std::stod(metaOr(set, meta::kOptimizeSeconds, "0"));
    const std::string settings = metaOr(set, meta::kSettings, "");
    const auto seed = settingOf(settings, "seed");
    const std::string *recordedSeed = findMeta(set, meta::kSeed);
    if (seed || recordedSeed) entry.seed = std::stoull(seed ? *seed : *recordedSeed);
    if (const auto epochs = settingOf(settings, "epochs")) entry.epochs = std::stoi(*epochs);
    entry.neural = file.filename().string().starts_with("neural_");
    if (entry.neural) entry.model = metaOr(set, meta::kModel, "?");
    entry.prefixes = metaOr(set, meta::kPrefixes, "");
    if (const auto weight = settingOf(settings, "union"))
      entry.unionWeight = std::stod(weight->substr(0, weight->find('/')));
  } catch (const std::exception &) {
    entry.target = "(unreadable)";
    entry.n = entry.instances = 0;
  }
  return entry;
}

std::vector<SetCache::Entry> SetCache::list() const {
  std::vector<Entry> out;
  for (const auto &e : filesIn(setsDir()))
    if (isEntry(e)) out.push_back(describe(e.path()));
  std::sort(out.begin(), out.end(),
            [](const Entry &a, const Entry &b) { return a.file.filename() < b.file.filename(); });
  return out;
}

std::string humanBytes(std::uintmax_t bytes) {
  const char *units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  double v = double(bytes);
  int u = 0;
  while (v >= 1024 && u < 4) v /= 1024, ++u;
  char out[32];
  std::snprintf(out, sizeof out, u ? "%.1f %s" : "%.0f %s", v, units[u]);
  return out;
}

std::string humanAge(std::chrono::seconds age) {
  const long long s = std::max<long long>(0, age.count());
  if (s < 120) return std::to_string(s) + "s";
  if (s < 120 * 60) return std::to_string(s / 60) + "m";
  if (s < 48 * 3600) return std::to_string(s / 3600) + "h";
  return std::to_string(s / 86400) + "d";
}

std::vector<std::string> setListing(const std::vector<std::string> &leadHeaders,
                                    const std::vector<SetListingRow> &rows,
                                    fs::file_time_type now) {
  // Every column but the target (last, whole) is padded to its widest cell;
  // text columns align left, numbers right.
  std::vector<std::string> headers = leadHeaders;
  const std::size_t lead = headers.size();
  for (const char *h : {"n", "instances", "seed", "epochs", "optimize_s", "size", "age", "kind",
                        "nested", "union", "key", "target"})
    headers.push_back(h);
  std::vector<std::vector<std::string>> cells;
  for (const SetListingRow &row : rows) {
    const SetCache::Entry &e = row.entry;
    std::vector<std::string> line = row.lead;
    line.resize(lead);
    const auto age = std::chrono::duration_cast<std::chrono::seconds>(now - e.modified);
    line.push_back(std::to_string(e.n));
    line.push_back(std::to_string(e.instances));
    line.push_back(e.seed ? std::to_string(*e.seed) : "-");
    line.push_back(e.epochs ? std::to_string(*e.epochs) : "-");
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.1f", e.optimizeSeconds);
    line.push_back(seconds);
    line.push_back(humanBytes(e.bytes));
    line.push_back(humanAge(age));
    line.push_back(e.neural ? "neural:" + e.model : e.n ? "optimized" : "-");
    line.push_back(e.prefixes.empty() ? "-" : e.prefixes);
    line.push_back(e.neural || !e.n ? "-" : formatRoundTrip(e.unionWeight));
    line.push_back(e.key.empty() ? "-" : e.key);
    line.push_back(e.target);
    cells.push_back(std::move(line));
  }
  return padColumns(headers, cells, [&](std::size_t c) { return c >= lead && c < lead + 6; });
}

std::vector<std::string> padColumns(const std::vector<std::string> &headers,
                                    const std::vector<std::vector<std::string>> &cells,
                                    const std::function<bool(std::size_t)> &numeric) {
  std::vector<std::size_t> width(headers.size(), 0);
  for (std::size_t c = 0; c < headers.size(); ++c) {
    width[c] = headers[c].size();
    for (const auto &line : cells) width[c] = std::max(width[c], line[c].size());
  }
  const auto format = [&](const std::vector<std::string> &line) {
    std::string out;
    for (std::size_t c = 0; c < line.size(); ++c) {
      if (c) out += "  ";
      const std::string pad(c + 1 < line.size() ? width[c] - line[c].size() : 0, ' ');
      out += numeric(c) ? pad + line[c] : line[c] + pad;
    }
    return out;
  };
  std::vector<std::string> out{format(headers)};
  for (const auto &line : cells) out.push_back(format(line));
  return out;
}

std::vector<SetCache::Checkpoint> SetCache::checkpoints() const {
  std::vector<Checkpoint> out;
  std::error_code ec;
  for (const auto &e : filesIn(setsDir()))
    if (e.path().extension() == ".ckpt")
      out.push_back({e.path(), e.file_size(ec), e.last_write_time(ec)});
  std::sort(out.begin(), out.end(),
            [](const Checkpoint &a, const Checkpoint &b) { return a.file < b.file; });
  return out;
}

std::uintmax_t SetCache::bytes() const {
  std::uintmax_t total = 0;
  std::error_code ec;
  for (const auto &e : filesIn(setsDir())) total += e.file_size(ec);
  return total;
}

CacheRemoval &CacheRemoval::operator+=(const CacheRemoval &other) {
  freed += other.freed;
  removed += other.removed;
  failed.insert(failed.end(), other.failed.begin(), other.failed.end());
  skipped.insert(skipped.end(), other.skipped.begin(), other.skipped.end());
  return *this;
}

CacheRemoval SetCache::clear() const {
  CacheRemoval out;
  for (const auto &e : filesIn(setsDir()))
    if (isCacheFile(e)) removeInto(e.path(), out);
  return out;
}

CacheRemoval SetCache::remove(const std::string &key) const {
  CacheRemoval out;
  for (const auto &e : filesIn(setsDir())) {
    const std::string name = e.path().filename().string();
    if (isCacheFile(e) && !name.starts_with(".") &&
        name.find("_" + key + ".ptsb") != std::string::npos)
      removeInto(e.path(), out);
  }
  return out;
}

std::vector<std::string> SetCache::verify() const {
  std::vector<std::string> out;
  for (const Entry &e : list())
    if (const std::string why = entryProblem(e.file); !why.empty())
      out.push_back(e.file.string() + ": " + why);
  return out;
}

namespace {

// entryProblem, with the sets read into `set` when there is none.
std::string problemOf(const fs::path &file, PointSet &set) {
  try {
    set = readPointSet(file.string());
    const std::string recorded = metaOr(set, meta::kCacheKey, ""), key = keyOf(file);
    if (recorded != key)
      return recorded.empty() ? "it records no cache key (written by an older nuld, or not by nuld)"
                              : "it records the key " + recorded + ", not its name's " + key +
                                    " (a file copied over another entry)";
    return "";
  } catch (const std::exception &e) {
    // readPointSet's message begins with the path; the reason is what follows.
    const std::string what = e.what(), prefix = file.string() + ": ";
    return what.starts_with(prefix) ? what.substr(prefix.size()) : what;
  }
}

}  // namespace

std::string entryProblem(const fs::path &file) {
  PointSet set;
  return problemOf(file, set);
}

std::optional<PointSet> readVerifiedEntry(const fs::path &file) {
  std::error_code ec;
  if (!fs::exists(file, ec)) return std::nullopt;
  PointSet set;
  const std::string why = problemOf(file, set);
  if (why.empty()) return set;
  fs::path aside = file;
  aside += ".corrupt";
  fs::rename(file, aside, ec);
  if (ec)
    throw std::runtime_error(file.string() + ": a damaged set cache entry (" + why +
                             ") that cannot be moved aside (" + ec.message() +
                             "); remove it with nuld cache remove " + keyOf(file));
  std::cerr << "\nnuld: note: the set cache entry " << file.string() << " is not served (" << why
            << "); moved to " << aside.filename().string() << ", and made again\n";
  return std::nullopt;
}

bool verifiedEntry(const fs::path &file) { return readVerifiedEntry(file).has_value(); }

void writeCacheEntry(const fs::path &file, PointSet sets) {
  if (const std::string key = keyOf(file); !key.empty()) setMeta(sets, meta::kCacheKey, key);
  fs::create_directories(file.parent_path());
  writePointSet(file.string(), sets);
}

}  // namespace nuld
