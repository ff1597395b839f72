#include "sampler/plugin.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

namespace nuld {
namespace {

using Entry = const void *(*)(int *);

std::vector<std::string> candidates(const PluginSpec &spec) {
  std::vector<std::string> places;
  if (const char *named = std::getenv(spec.variable); named && *named) places.push_back(named);
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) places.push_back((self.parent_path() / spec.file).string());
#ifdef NULD_PLUGIN_DIR
  const std::string built = (std::filesystem::path(NULD_PLUGIN_DIR) / spec.file).string();
  if (std::find(places.begin(), places.end(), built) == places.end()) places.push_back(built);
#endif
  return places;
}

// The plugin's interface object from the file at `place`, or nullptr with
// `why` saying what is wrong with it; `rebuild` says what to do about a
// version mismatch.
const void *loadFrom(const std::string &place, const PluginSpec &spec, const char *rebuild,
                     std::string &why, int &version) {
  if (!std::filesystem::exists(place)) {
    why = "no such file";
    return nullptr;
  }
  // RTLD_LOCAL: the plugin's own copy of nuld's code stays its own.
  void *plugin = dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!plugin) {
    const char *error = dlerror();
    why = error ? error : "not loadable";
    return nullptr;
  }
  const auto entry = reinterpret_cast<Entry>(dlsym(plugin, spec.entry));
  if (!entry) {
    why = std::string("not the plugin (no ") + spec.entry + ")";
    return nullptr;
  }
  version = 0;
  const void *object = entry(&version);
  const int oldest = spec.oldestVersion > 0 ? spec.oldestVersion : spec.version;
  if (version < oldest || version > spec.version) {
    why = "built for interface version " + std::to_string(version) + ", expected " +
          (oldest < spec.version ? std::to_string(oldest) + " to " + std::to_string(spec.version)
                                 : std::to_string(spec.version)) +
          " (" + rebuild + ")";
    return nullptr;
  }
  if (!object) why = std::string(spec.entry) + " returned no interface";
  return object;
}

const void *load(const PluginSpec &spec) {
  std::string tried;
  for (const std::string &place : candidates(spec)) {
    std::string why;
    int version;
    if (const void *object = loadFrom(place, spec, "rebuild nuld", why, version)) return object;
    tried += "\n  " + place + ": " + why;
  }
  throw std::runtime_error(
      std::string(spec.purpose) + " needs nuld's plugin " + spec.file + "; tried:" + tried +
      "\n(build it with tools/build.sh, or name it with " + spec.variable + ")");
}

std::mutex &loaderLock() {
  static std::mutex lock;
  return lock;
}

}  // namespace

const void *loadPlugin(const PluginSpec &spec) {
  static std::map<std::pair<std::string, int>, const void *> loaded;  // by entry and version
  const std::lock_guard guard(loaderLock());
  const void *&object = loaded[{spec.entry, spec.version}];
  if (!object) object = load(spec);
  return object;
}

const void *loadPluginFile(const std::string &path, const PluginSpec &spec,
                           const std::string &rebuild, int *version) {
  // By the file's canonical path: the interface and its version.
  static std::map<std::string, std::pair<const void *, int>> loaded;
  std::error_code error;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, error);
  const std::string key = error ? path : canonical.string();
  const std::lock_guard guard(loaderLock());
  auto &[object, found] = loaded[key];
  if (!object) {
    std::string why;
    // dlopen searches the library path for a name without a slash: a file
    // in the working directory is meant.
    const std::string place = path.find('/') == std::string::npos ? "./" + path : path;
    object = loadFrom(place, spec, rebuild.c_str(), why, found);
    if (!object) throw std::runtime_error(std::string(spec.purpose) + " " + path + ": " + why);
  }
  if (version) *version = found;
  return object;
}

}  // namespace nuld
