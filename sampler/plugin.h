#pragma once
// Heavy libraries as plugins loaded on first use. Linked, LibTorch and
// OpenImageIO (with the hundreds of libraries OpenImageIO links) cost every
// process start far more than the rest of nuld, in relocations and static
// initializers (tools/experiments/startup_and_suite_time.md), and most
// processes never run a network or touch an image (every refused command line,
// most tests). So the code that calls them is built as a plugin of this build,
// and the first caller loads it (docs/architecture.md, "Build and
// dependencies").
//
// A plugin exports one C function, `const void *ENTRY(int *version)`: it
// writes the interface version it was built with and returns its interface
// object. A plugin is never unloaded (the objects it makes live until exit).

#include <string>

namespace nuld {

struct PluginSpec {
  const char *file;      // "libnuld_torch.so"
  const char *variable;  // an environment variable that names the file instead
  const char *entry;     // the exported function's name
  int version;           // the interface version the caller was built with
  const char *purpose;   // "the neural generator": what needs the plugin
  // The oldest version the caller still loads (0: `version` only); a plugin
  // of any version from it to `version` is accepted (loadPluginFile).
  int oldestVersion = 0;
};

// The plugin's interface object, loaded from (in this order) the file the
// spec's variable names, `file` beside the executable, or `file` in the
// build tree's root, where the build writes every plugin. Loaded once per
// process, entry and version; a failed load is tried again by the next
// call (the caller may have set the variable since). Throws
// std::runtime_error naming the purpose, each place tried and why it failed.
const void *loadPlugin(const PluginSpec &spec);

// The interface object of the plugin in the file `path` (a user's plugin,
// not one of this build's; the spec's file and variable are not used): its
// entry and version, no other place tried. Loaded once per file. Throws
// std::runtime_error starting with the spec's purpose and the path, saying
// what is wrong (no such file, not loadable, no entry, another version:
// then `rebuild`, what to do about it). `version`, if given, receives the
// version the plugin was built for.
const void *loadPluginFile(const std::string &path, const PluginSpec &spec,
                           const std::string &rebuild, int *version = nullptr);

}  // namespace nuld
