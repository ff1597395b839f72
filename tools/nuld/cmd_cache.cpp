// nuld cache: the shared set cache (tools/study/set_cache.h): where it is,
// what it holds and how much, and clearing it.

#include <cstdio>
#include <iostream>

#include "tools/nuld/commands.h"
#include "tools/study/set_cache.h"

namespace nuld::cli {

namespace {

std::string humanBytes(std::uintmax_t bytes) {
  const char *units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  double v = double(bytes);
  int u = 0;
  while (v >= 1024 && u < 4) v /= 1024, ++u;
  char out[32];
  std::snprintf(out, sizeof out, u ? "%.1f %s" : "%.0f %s", v, units[u]);
  return out;
}

}  // namespace

Runner addCache(CLI::App &app) {
  app.require_subcommand(1);
  app.footer(
      "The cache is $NULD_CACHE, else $XDG_CACHE_HOME/nuld, else ~/.cache/nuld. Its entries are\n"
      "keyed by content (the target's density, the optimizer's settings), so studies in any\n"
      "directory, nuld render and the Python module share them across asset roots.");
  CLI::App *list = app.add_subcommand("list", "List the cached sets: target, N, instances, size");
  CLI::App *clear = app.add_subcommand("clear", "Remove every cached set and checkpoint");
  CLI::App *path = app.add_subcommand("path", "Print the cache's directory");
  return [list, clear, path] {
    const study::SetCache cache = study::SetCache::fromEnvironment();
    if (path->parsed()) {
      std::cout << cache.root().string() << "\n";
      return 0;
    }
    if (clear->parsed()) {
      const std::uintmax_t freed = cache.clear();
      std::cout << "cleared " << cache.setsDir().string() << ": " << humanBytes(freed)
                << " freed\n";
      return 0;
    }
    (void)list;
    const auto entries = cache.list();
    std::printf("%-40s %6s %9s %10s %10s  %s\n", "target", "n", "instances", "size", "optimize_s",
                "file");
    for (const auto &e : entries)
      std::printf("%-40s %6zu %9zu %10s %10.1f  %s\n", e.target.substr(0, 40).c_str(), e.n,
                  e.instances, humanBytes(e.bytes).c_str(), e.optimizeSeconds,
                  e.file.filename().string().c_str());
    std::printf("%zu entr%s, %s in %s\n", entries.size(), entries.size() == 1 ? "y" : "ies",
                humanBytes(cache.bytes()).c_str(), cache.setsDir().string().c_str());
    return 0;
  };
}

}  // namespace nuld::cli
