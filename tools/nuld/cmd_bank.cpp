// nuld bank: a scene's learned sets for a study backend, made into the set
// cache (or found there) exactly as a study or nuld render makes them, and
// listed by the pair and target they serve; with -o, copied into a bank
// directory that `--backend optimized:DIR` reads whole.

#include <filesystem>
#include <iostream>

#include "backends/ready_backend.h"
#include "backends/set_cache.h"
#include "sampler/io/output_folder.h"
#include "scenes/scene_file.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"
#include "tools/nuld/interrupt_note.h"
#include "tools/nuld/progress.h"

namespace nuld::cli {

Runner addBank(CLI::App &app) {
  struct Options {
    std::string scene, backend = "optimized-both", res, assets, integrator, output;
    std::vector<std::size_t> spp;
    double resScale = 1;
    std::int64_t seed = -1;
    SetSettings sets;
    SceneChoices choices;
    bool quiet = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("scene", o->scene,
                 "scene file (JSON, or glTF .gltf/.glb) or a built-in scene: " + builtInSceneList())
      ->required();
  app.add_option("--backend", o->backend,
                 "optimized, optimized-uniform, optimized-bsdf or optimized-both (default "
                 "optimized-both)")
      ->check(parsedBy([](const std::string &word) {
        if (parseBackendWord(word).sets == BackendSets::None)
          throw std::invalid_argument("'" + word +
                                      "': nuld bank makes the study's sets (optimized, "
                                      "optimized-uniform, optimized-bsdf, optimized-both)");
      }));
  app.add_option("--spp", o->spp, "comma-separated sample counts (default: the scene's)")
      ->delimiter(',');
  app.add_option("--res", o->res, "resolution the lobe bins are chosen at (WxH or W)")
      ->check(parsedBy(parseResolution));
  app.add_option("--res-scale", o->resScale, "scale the scene's resolution (not with --res)")
      ->check(numberIn(1e-6, 16));
  app.add_option("--integrator", o->integrator,
                 "path, direct, light or bsdf (default: the scene's)")
      ->check(oneOf(kIntegratorNames));
  app.add_option("--seed", o->seed,
                 "seed of the optimization (a study's or nuld render's --seed; default: the "
                 "scene's, else " +
                     std::to_string(kDefaultSeed) + ", as theirs)")
      ->check(wholeNumberIn(0, std::int64_t(1) << 62));
  addSetOptions(app, o->sets);
  addSceneChoiceOptions(app, o->choices);
  app.add_option("--assets", o->assets,
                 "asset root (default: $NULD_ASSETS, else ../shared/assets)");
  app.add_option("-o,--output", o->output,
                 "also copy the sets into this bank directory (for --backend optimized:DIR)");
  app.add_flag("-q,--quiet", o->quiet, "no progress bar");
  app.footer(
      "Prints one line per set: spp, the pair it serves (light or bsdf), whether this command\n"
      "made it or found it in the set cache ($NULD_CACHE), then the columns of nuld cache list:\n"
      "N, instances, seed, epochs, optimization seconds, size, age, key (the file's name ends in\n"
      "_KEY.ptsb) and the whole target.");
  return [o, &app] {
    const BackendWord word = parseBackendWord(o->backend);
    checkAssets(app, o->assets, !isBuiltInScene(o->scene), kSceneFilesOnly);
    LoadedScene loaded = loadScene(o->scene, resolveAssetRoot(o->assets), o->choices);
    RenderOverrides change;
    applyResolution(app, o->res, o->resScale, change);
    if (!o->integrator.empty()) change.integrator = parseIntegrator(o->integrator);
    RenderSettings s = change.appliedTo(loaded.settings);
    if (o->spp.empty()) o->spp = {s.spp};
    const std::uint64_t seed = o->seed >= 0 ? std::uint64_t(o->seed) : loaded.seed;
    if (!o->output.empty()) claimOutputFolder(o->output, "bank");
    std::vector<SetListingRow> rows;
    std::filesystem::path dir;
    // Sets are made with checkpoints in the set cache, and a rerun
    // continues them by itself.
    const std::string setsDir = setsDirectory(o->sets);
    const InterruptNote interruptNote(setsDir, setsInterruptNote(setsDir));
    for (const std::size_t spp : o->spp) {
      s.spp = spp;
      ProgressBar bar("sets spp " + std::to_string(spp), 1000, 0, o->quiet);
      const PreparedBackend p =
          prepareBackend(word, loaded.scene, s, slug(o->scene), o->sets, seed, o->spp,
                         [&](const std::string &, double f, const std::string &status) {
                           bar.update(long(1000 * f), status);
                         });
      bar.finish(std::to_string(p.setsMade) + " made, " + std::to_string(p.setsCached) + " cached");
      if (!p.note.empty()) std::cerr << "nuld: note: " << p.note << "\n";
      for (const auto &set : p.sets) {
        const bool lobe = set.target.rfind("disney", 0) == 0;
        rows.push_back({{std::to_string(spp),
                         lobe                      ? "bsdf"
                         : set.target == "uniform" ? "any"
                                                   : "light",
                         set.made ? "made" : "cached"},
                        SetCache::describe(set.file)});
        dir = std::filesystem::path(set.file).parent_path();
        if (!o->output.empty())
          std::filesystem::copy_file(
              set.file,
              std::filesystem::path(o->output) / std::filesystem::path(set.file).filename(),
              std::filesystem::copy_options::overwrite_existing);
      }
    }
    for (const std::string &line : setListing({"spp", "pair", "state"}, rows))
      std::cout << line << "\n";
    if (!rows.empty())
      std::cout << rows.size() << (rows.size() == 1 ? " set" : " sets") << " in " << dir.string()
                << " (each file's name ends in _KEY.ptsb)\n";
    return 0;
  };
}

}  // namespace nuld::cli
