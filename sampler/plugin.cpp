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

const void *load(const PluginSpec &spec) {
  std::string tried;
  for (const std::string &place : candidates(spec)) {
    if (!std::filesystem::exists(place)) {
      tried += "\n  " + place + ": no such file";
      continue;
    }
    // RTLD_LOCAL: the plugin's own copy of nuld's code stays its own.
    void *plugin = dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!plugin) {
      const char *why = dlerror();
      tried += "\n  " + place + ": " + (why ? why : "not loadable");
      continue;
    }
    const auto entry = reinterpret_cast<Entry>(dlsym(plugin, spec.entry));
    if (!entry) {
      tried += "\n  " + place + ": not the plugin (no " + spec.entry + ")";
      continue;
    }
    int version = 0;
    const void *object = entry(&version);
    if (version != spec.version) {
      tried += "\n  " + place + ": built for interface version " + std::to_string(version) +
               ", expected " + std::to_string(spec.version) + " (rebuild nuld)";
      continue;
    }
    return object;
  }
  throw std::runtime_error(
      std::string(spec.purpose) + " needs nuld's plugin " + spec.file + "; tried:" + tried +
      "\n(build it with tools/build.sh, or name it with " + spec.variable + ")");
}

}  // namespace

const void *loadPlugin(const PluginSpec &spec) {
  static std::mutex lock;
  static std::map<std::pair<std::string, int>, const void *> loaded;  // by entry and version
  const std::lock_guard guard(lock);
  const void *&object = loaded[{spec.entry, spec.version}];
  if (!object) object = load(spec);
  return object;
}

}  // namespace nuld
