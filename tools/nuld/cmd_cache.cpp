// nuld cache: the shared caches of sets (backends/set_cache.h) and of
// references (backends/reference_cache.h): where they are, what they hold
// and how much, and clearing them.

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "backends/reference_cache.h"
#include "backends/set_cache.h"
#include "tools/nuld/cli_util.h"
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
  CLI::App *clear = app.add_subcommand(
      "clear",
      "Remove every cached set, checkpoint and reference (a reference another process is "
      "making or reading is skipped and named); exits 1 when a file could not be removed");
  CLI::App *remove = app.add_subcommand(
      "remove",
      "Remove the entries of one key (a set or a reference; the KEY column of nuld "
      "cache list) or the references of one scene");
  auto key = std::make_shared<std::string>(), scene = std::make_shared<std::string>();
  remove->add_option("key", *key, "an entry's key: 16 hex digits, as nuld cache list shows it");
  remove->add_option("--scene", *scene, "the references of this scene (the list's scene column)");
  CLI::App *verify = app.add_subcommand(
      "verify",
      "Check every entry as a use checks it (sets: checksum and recorded key; references: "
      "each image's decoding, description and pixel hash) and name each that would not be "
      "served; exits 1 when one fails");
  CLI::App *path = app.add_subcommand("path", "Print the cache's directory");
  return [list, clear, remove, verify, path, key, scene] {
    const SetCache cache = SetCache::fromEnvironment();
    const ReferenceCache references = ReferenceCache::fromEnvironment();
    if (path->parsed()) {
      std::cout << cache.root().string() << "\n";
      return 0;
    }
    // A cache that is not a folder is a mistake to say, not an empty cache.
    for (const std::filesystem::path &dir : {cache.root(), references.referencesDir()})
      if (std::error_code ec;
          std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
        throw std::invalid_argument(
            dir.string() +
            ": the cache (NULD_CACHE, NULD_REFERENCE_CACHE) names something "
            "that is not a folder; expected a folder");
    if (clear->parsed() || remove->parsed()) {
      if (remove->parsed()) {
        if (key->empty() == scene->empty())
          throw UsageError("cache remove: name a KEY or --scene NAME (one of them)");
        if (!key->empty() &&
            (key->size() != 16 || key->find_first_not_of("0123456789abcdef") != std::string::npos))
          throw UsageError("cache remove: '" + *key +
                           "' is not a key; expected 16 hex digits (nuld cache list)");
      }
      CacheRemoval sets = clear->parsed() ? cache.clear()
                          : key->empty()  ? CacheRemoval{}
                                          : cache.remove(*key);
      const CacheRemoval refs =
          clear->parsed() ? references.clear() : references.remove(*key, *scene);
      std::cout << (clear->parsed() ? "cleared " : "removed from ") << cache.setsDir().string()
                << ": " << sets.removed << " files, " << humanBytes(sets.freed) << " freed\n";
      std::cout << (clear->parsed() ? "cleared " : "removed from ")
                << references.referencesDir().string() << ": " << refs.removed << " files, "
                << humanBytes(refs.freed) << " freed\n";
      sets += refs;
      for (const std::string &s : sets.skipped) std::cout << "skipped " << s << "\n";
      for (const std::string &f : sets.failed) std::cerr << "nuld: cannot remove " << f << "\n";
      if (remove->parsed() && sets.removed == 0 && sets.skipped.empty() && sets.failed.empty())
        throw std::invalid_argument(
            "cache remove: no entry " +
            (key->empty() ? "of scene '" + *scene + "'" : "of key " + *key) +
            " (nuld cache list shows them)");
      return sets.failed.empty() ? 0 : 1;
    }
    if (verify->parsed()) {
      std::vector<std::string> problems = cache.verify();
      for (const std::string &p : references.verify()) problems.push_back(p);
      const std::size_t entries = cache.list().size() + references.list().size();
      for (const std::string &p : problems) std::cout << "damaged " << p << "\n";
      std::cout << entries - std::min(entries, problems.size()) << " of " << entries
                << " entries verified"
                << (problems.empty() ? ""
                                     : "; a damaged one is never served: the next use "
                                       "moves it aside and makes it again (or nuld cache "
                                       "remove KEY)")
                << "\n";
      return problems.empty() ? 0 : 1;
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
      for (const auto &c : checkpoints) {
        // Beside a complete entry a checkpoint is stale: nothing continues it.
        const bool stale = std::filesystem::exists(std::filesystem::path(c.file).replace_extension());
        std::cout << "  " << humanBytes(c.bytes) << "  "
                  << humanAge(std::chrono::duration_cast<std::chrono::seconds>(now - c.modified))
                  << "  " << c.file.filename().string()
                  << (stale ? "  (stale: its entry is complete)" : "") << "\n";
      }
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
