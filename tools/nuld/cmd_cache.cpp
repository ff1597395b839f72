// nuld cache: the shared caches of sets (backends/set_cache.h) and of
// references (backends/reference_cache.h): where they are, what they hold
// and how much, and clearing them.

#include <chrono>
#include <filesystem>
#include <iostream>

#include "backends/reference_cache.h"
#include "backends/set_cache.h"
#include "tools/nuld/commands.h"

namespace nuld::cli {

Runner addCache(CLI::App &app) {
  app.require_subcommand(1);
  app.footer(
      "The cache is $NULD_CACHE, else $XDG_CACHE_HOME/nuld, else ~/.cache/nuld (references:\n"
      "$NULD_REFERENCE_CACHE, else its references/ folder). Its sets are\n"
      "keyed by content (the target's density, the optimizer's settings), its references by\n"
      "the scene's content (meshes, materials, map pixels, camera) and every render setting,\n"
      "so studies in any directory, nuld render and the Python module share them across\n"
      "asset roots.");
  CLI::App *list = app.add_subcommand(
      "list",
      "List the cached sets (N, instances, seed, epochs, size, age, kind, nesting, bank term "
      "weight, key, target), then any checkpoints with their size and age, then the references "
      "(scene, resolution, integrator, spp, backend, complete or the passes done, render "
      "seconds, size, age, key)");
  CLI::App *clear =
      app.add_subcommand("clear", "Remove every cached set, checkpoint and reference");
  CLI::App *path = app.add_subcommand("path", "Print the cache's directory");
  return [list, clear, path] {
    const SetCache cache = SetCache::fromEnvironment();
    const ReferenceCache references = ReferenceCache::fromEnvironment();
    if (path->parsed()) {
      std::cout << cache.root().string() << "\n";
      return 0;
    }
    if (clear->parsed()) {
      const std::uintmax_t freed = cache.clear();
      std::cout << "cleared " << cache.setsDir().string() << ": " << humanBytes(freed)
                << " freed\n";
      const std::uintmax_t referencesFreed = references.clear();
      std::cout << "cleared " << references.referencesDir().string() << ": "
                << humanBytes(referencesFreed) << " freed\n";
      return 0;
    }
    (void)list;
    const auto entries = cache.list();
    std::vector<SetListingRow> rows;
    for (const auto &e : entries) rows.push_back({{}, e});
    for (const std::string &line : setListing({}, rows)) std::cout << line << "\n";
    std::cout << entries.size() << (entries.size() == 1 ? " entry, " : " entries, ")
              << humanBytes(cache.bytes()) << " in " << cache.setsDir().string()
              << " (each file's name ends in _KEY.ptsb)\n";
    const auto checkpoints = cache.checkpoints();
    if (!checkpoints.empty()) {
      std::cout << "\n"
                << checkpoints.size() << (checkpoints.size() == 1 ? " checkpoint" : " checkpoints")
                << " of sets being made or left by an interrupted run (the same command "
                   "continues one; nuld cache clear removes them):\n";
      const auto now = std::filesystem::file_time_type::clock::now();
      for (const auto &c : checkpoints)
        std::cout << "  " << humanBytes(c.bytes) << "  "
                  << humanAge(std::chrono::duration_cast<std::chrono::seconds>(now - c.modified))
                  << "  " << c.file.filename().string() << "\n";
    }
    const auto refs = references.list();
    std::cout << "\n";
    if (!refs.empty())
      for (const std::string &line : referenceListing(refs)) std::cout << line << "\n";
    std::cout << refs.size() << (refs.size() == 1 ? " reference, " : " references, ")
              << humanBytes(references.bytes()) << " in " << references.referencesDir().string()
              << " (one directory each, its name ending in _KEY; one in progress continues "
                 "when a study or nuld render --reference asks for it again)\n";
    return 0;
  };
}

}  // namespace nuld::cli
