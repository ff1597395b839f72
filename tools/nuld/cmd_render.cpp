// nuld render: a scene file (or the built-in `default`) with a chosen sampler
// backend to an EXR plus a tone-mapped PNG preview.

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "backends/backend_registry.h"
#include "backends/ready_backend.h"
#include "backends/reference_cache.h"
#include "renderer/flip.h"
#include "renderer/image_metrics.h"
#include "renderer/render.h"
#include "sampler/diagnostics.h"
#include "sampler/io/atomic_file.h"
#include "scenes/scene_file.h"
#include "tools/nuld/cli_util.h"
#include "tools/nuld/commands.h"
#include "tools/nuld/interrupt_note.h"
#include "tools/nuld/progress.h"

namespace nuld::cli {

namespace {

// Where a study word's sets came from, in one sentence.
std::string setsSentence(const std::string &word, const PreparedBackend &p) {
  const std::string all = std::to_string(p.setsMade + p.setsCached);
  if (p.setsMade == 0) return word + ": its " + all + " sets came from the set cache";
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.1f", p.setupSeconds);
  return word + ": " + std::to_string(p.setsMade) + " of its " + all + " sets were made in " +
         seconds + " s (now in the set cache)" +
         (p.setsCached ? ", " + std::to_string(p.setsCached) + " came from the cache" : "");
}

// The pairs a learned backend serves: those whose sets served a context
// (sets that follow none of the scene's targets are refused when the
// backend is prepared, so a pair that served nothing has no sets).
std::vector<SamplerBackend::PairUse> servedPairs(std::vector<SamplerBackend::PairUse> use) {
  std::erase_if(use, [](const SamplerBackend::PairUse &u) { return u.served == 0; });
  return use;
}

// Why a context falls back when nothing more precise is known.
const std::string kNoSetReason =
    "no set of the backend follows their target (the map, or the lobe bin of their material)";

// The reasons a study word's plan and the backend itself gave, as one ("" when
// neither gave one; fallbackNote then says kNoSetReason).
std::string joinReasons(const std::string &plan, const std::string &backend) {
  if (backend.empty()) return plan;
  return (plan.empty() ? kNoSetReason : plan) + "; " + backend;
}

// One note when the served pairs fell back for some first-bounce contexts:
// the share served and why the rest fell back (the plan's and the
// backend's reasons); when all were served, what the backend decided alone.
std::string fallbackNote(const std::string &backend,
                         const std::vector<SamplerBackend::PairUse> &served,
                         const std::string &plan, const std::string &decided) {
  const std::string why = joinReasons(plan, decided);
  std::uint64_t ok = 0, all = 0;
  std::string parts;
  for (const auto &u : served) {
    ok += u.served, all += u.served + u.fellBack;
    parts += (parts.empty() ? "" : ", ") + u.pair + " " + std::to_string(u.served) + " of " +
             std::to_string(u.served + u.fellBack);
  }
  if (ok == all) return decided;  // what the backend decided still stands
  char share[16];
  std::snprintf(share, sizeof share, "%.0f %%", 100.0 * double(ok) / double(all));
  return backend + " served " + share + " of its first-bounce contexts (" + parts +
         "); the rest sampled the classic Owen-Sobol route: " + (why.empty() ? kNoSetReason : why);
}

// --reference: the scene's reference as a study makes it (passes, two
// halves, the reference cache), copied to `output` with its halves beside it.
int renderCachedReference(const LoadedScene &loaded, const ReferenceSettings &settings,
                          std::size_t stopAfter, const std::string &output, bool quiet) {
  const ReferenceCache cache = ReferenceCache::fromEnvironment();
  // Ctrl-C or SIGTERM ends the reference with the note every long command
  // prints (also when started with SIGINT ignored, as a script's `&` does).
  const InterruptNote interruptNote(cache.referencesDir().string(),
                                    "the passes rendered so far are kept in the reference cache, " +
                                        cache.referencesDir().string() +
                                        ": run the same command again to continue them");
  ProgressBar bar("reference", 1000, 0, quiet);
  const CachedReference ref = cachedReference(
      loaded.scene, slug(loaded.name), settings, cache,
      [&](const ReferenceProgress &p) {
        bar.update(long(1000 * p.fraction), referenceProgressText(p));
      },
      stopAfter);
  bar.finish(ref.found ? "found in the cache" : formatDuration(ref.result.seconds));
  if (!ref.result.complete) {
    std::cerr << "nuld: note: the reference stopped after --reference-stop-after " << stopAfter
              << " passes, saved in " << ref.dir.string()
              << "; run the same command again to continue it\n";
    return 0;
  }
  const std::filesystem::path out(output);
  const std::filesystem::path stem = std::filesystem::path(out).replace_extension();
  for (const auto &[from, to] :
       {std::pair{ref.dir / "reference.half0.exr", stem.string() + ".half0.exr"},
        std::pair{ref.dir / "reference.half1.exr", stem.string() + ".half1.exr"},
        std::pair{ref.dir / "reference.png", stem.string() + ".png"},
        std::pair{ref.dir / "reference.exr", out.string()}})
    copyFileAtomically(from, to);
  std::cerr << "nuld: "
            << (ref.found ? "the reference was found in the cache: "
                          : "the reference is now in the cache: ")
            << ref.dir.string() << "\n";
  std::printf("scene %s\nbackend %s\nspp %zu\nresolution %dx%d\nintegrator %s\n",
              loaded.name.c_str(), settings.backend.c_str(), settings.totalSpp(),
              settings.render.width, settings.render.height,
              toString(settings.render.integrator).c_str());
  std::printf("cache %s\nseconds %.3f\nmade_seconds %.3f\nvariance %.6g\nrelvariance %.6g\n",
              ref.found ? "found" : "rendered", ref.found ? 0.0 : ref.result.seconds,
              ref.result.totalSeconds, ref.result.noise.variance, ref.result.noise.relVariance);
  return 0;
}

}  // namespace

Runner addRender(CLI::App &app) {
  struct Options {
    std::string scene, backend, res, assets, integrator, output;
    std::size_t spp = 0;
    int maxDepth = 0;
    RenderOverrides change;  // --lobe-*; the rest is set from the options below
    SceneChoices choices;
    std::int64_t seed = -1;
    SetSettings sets;  // --opt-*: the study backends' sets
    double resScale = 1;
    bool quiet = false;
    bool reference = false;
    std::size_t referencePassSpp = ReferenceSettings{}.passSpp, referenceStopAfter = 0;
  };
  auto o = std::make_shared<Options>();
  app.add_option(
         "scene", o->scene,
         "scene file (JSON, or glTF .gltf/.glb) or a built-in scene, which needs no files: " +
             builtInSceneList())
      ->required();
  app.add_option("--backend", o->backend,
                 "sampler backend: " + backendSpellings(kRenders) +
                     " (optimized without PATHS, optimized-uniform, optimized-bsdf and "
                     "optimized-both make their sets once into the set cache, or find them "
                     "there; +shift for shifted sets) (default: the scene's, else sobol; nuld "
                     "help backends says what each samples)")
      ->check(studyBackendWord());
  app.add_option("--spp", o->spp, "samples per pixel (default: the scene's)")
      ->check(wholeNumberIn(1, 1 << 24));
  app.add_option("--res", o->res,
                 "resolution WxH, or W keeping the scene's aspect (default: the scene's)")
      ->check(parsedBy(parseResolution));
  app.add_option("--res-scale", o->resScale,
                 "scale the scene's own resolution (e.g. 0.25; not with --res)")
      ->check(numberIn(1e-6, 16));
  app.add_option("--assets", o->assets,
                 "asset root for the scene's meshes and maps (default: $NULD_ASSETS, else "
                 "../shared/assets beside the checkout)");
  app.add_option("--integrator", o->integrator,
                 "path, direct (first bounce, MIS of light and BSDF sampling), light (first "
                 "bounce, light sampling only) or bsdf (first bounce, BSDF sampling only)")
      ->check(oneOf(kIntegratorNames));
  app.add_option("--max-depth", o->maxDepth, "maximum path length in bounces")
      ->check(wholeNumberIn(1, kMaxDepthLimit));
  addLobeOptions(app, o->change);
  addSceneChoiceOptions(app, o->choices);
  addSetOptions(app, o->sets);
  app.add_option("--seed", o->seed,
                 "seed of the backend's randomization and of the sets it makes (default: the "
                 "scene's, else " +
                     std::to_string(kDefaultSeed) + ", as nuld bank's and the studies')")
      ->check(wholeNumberIn(0, std::int64_t(1) << 62));
  app.add_option("-o,--output", o->output, "output EXR (a tone-mapped PNG is written beside it)")
      ->required()
      ->check(parsedBy(checkRenderName));
  app.add_flag("-q,--quiet", o->quiet, "no progress bar");
  app.add_flag("--reference", o->reference,
               "render the scene's reference as a study does: --spp in all (default " +
                   std::to_string(ReferenceSettings{}.spp) +
                   ") in resumable passes of two independent halves (written beside OUTPUT as "
                   ".half0.exr and .half1.exr), with --backend (default halton) and --seed "
                   "(default " +
                   std::to_string(ReferenceSettings{}.seed) +
                   ", the studies'); kept in the reference cache (nuld cache list), where a "
                   "study with the same scene content and settings finds it, and found there");
  app.add_option("--reference-pass-spp", o->referencePassSpp,
                 "with --reference: spp per resumable pass (default 256)")
      ->check(wholeNumberIn(1, 1 << 24));
  app.add_option("--reference-stop-after", o->referenceStopAfter,
                 "with --reference: render at most this many passes in this run, then stop "
                 "with the passes saved in the cache (a rerun continues them)")
      ->check(wholeNumberIn(1, 1 << 24));
  return [o, &app] {
    checkRenderOutputs(o->output);
    checkAssets(app, o->assets, !isBuiltInScene(o->scene), kSceneFilesOnly);
    LoadedScene loaded = loadScene(o->scene, resolveAssetRoot(o->assets), o->choices);
    RenderOverrides change = o->change;
    if (o->spp) change.spp = o->spp;
    applyResolution(app, o->res, o->resScale, change);
    if (!o->integrator.empty()) change.integrator = parseIntegrator(o->integrator);
    if (o->maxDepth) change.maxDepth = o->maxDepth;
    // What the scene's settings with the command line's refuse (a render
    // the machine cannot hold, --max-depth under an integrator other than
    // path; the renderer's rules, which nuld.render applies too) is a usage
    // error, as the options' own checks are.
    RenderSettings s;
    try {
      s = change.appliedTo(loaded.settings);
      change.checkApplicable(s, OverrideNames::options());
    } catch (const std::invalid_argument &e) {
      throw UsageError(std::string("render: ") + e.what());
    }
    onlyWhen(app, o->reference, {"--reference-pass-spp", "--reference-stop-after"}, "--reference");
    if (o->reference) {
      ReferenceSettings r;
      r.render = s;
      if (o->spp) r.spp = o->spp;
      r.passSpp = o->referencePassSpp;
      if (!o->backend.empty()) r.backend = o->backend;
      if (o->seed >= 0) r.seed = std::uint64_t(o->seed);
      if (parseBackendWord(r.backend).sets != BackendSets::None)
        throw UsageError(
            "render: --reference renders with a classic backend (halton, sobol, "
            "independent, ...), not '" +
            r.backend + "', whose sets would bias it");
      onlyWhen(app, false, kSetOptionNames,
               "renders of the backends that make sets (not --reference)");
      onlyWhen(app, parseBackendWord(r.backend).samplesLobes(), kLobeOptionNames,
               "a reference backend that samples lobe tables (sobol-tabulated)");
      return renderCachedReference(loaded, r, o->referenceStopAfter, o->output, o->quiet);
    }
    const std::uint64_t seed = o->seed >= 0 ? std::uint64_t(o->seed) : loaded.seed;
    // A study word makes (or finds in the set cache) its sets as a study
    // with this seed would, then renders through the banks that serve them.
    const BackendWord word = parseBackendWord(o->backend.empty() ? loaded.backend : o->backend);
    onlyWhen(app, word.sets != BackendSets::None, kSetOptionNames,
             "the study's backends that make sets (optimized, optimized-bsdf, ...)");
    ReadyBackend ready;
    {
      // Sets are made with checkpoints in the set cache, and a rerun
      // continues them by itself.
      const std::string setsDir = setsDirectory(o->sets);
      std::optional<InterruptNote> interruptNote;
      if (word.sets != BackendSets::None)
        interruptNote.emplace(setsDir, setsInterruptNote(setsDir));
      ProgressBar setsBar("sets", 1000, 0, o->quiet || word.sets == BackendSets::None);
      ready = makeReadyBackend(word, loaded.scene, s, slug(o->scene), o->sets, seed, {},
                               [&](const std::string &, double f, const std::string &status) {
                                 setsBar.update(long(1000 * f), status);
                               });
      setsBar.finish(std::to_string(ready.prepared.setsMade) + " made, " +
                     std::to_string(ready.prepared.setsCached) + " from the cache");
    }
    const PreparedBackend &prepared = ready.prepared;
    if (word.sets != BackendSets::None)
      std::cerr << "nuld: " << setsSentence(word.word, prepared) << "\n";
    const std::unique_ptr<SamplerBackend> &backend = ready.backend;
    onlyWhen(app, backend->samplesLobes() && s.integrator != IntegratorKind::Light,
             kLobeOptionNames,
             "a backend that samples lobe tables (sobol-tabulated, lobe banks) and an integrator "
             "other than light");

    ProgressBar bar("render", 1000, 0, o->quiet);
    RenderStats stats;
    const Image image =
        render(loaded.scene, s, *backend, &stats, [&](std::size_t d, std::size_t n) {
          bar.update(long(1000 * d / n), std::to_string(d) + "/" + std::to_string(n) + " tiles");
        });
    bar.finish(formatDuration(stats.seconds));
    // One setup time, as the studies count it: the lobe tables, the backend
    // and the sets made for it.
    stats.setupSeconds += prepared.setupSeconds;
    // A backend of learned sets that served nothing rendered the classic
    // sampler's image under its name: refused, not written, unless it said
    // why it chose to (its note: sets measured worse than the fallback).
    const SamplerBackend::Report report = backend->report();
    const auto &use = report.pairUse;
    std::uint64_t served = 0;
    for (const auto &u : use) served += u.served;
    const std::string &decided = report.note;
    if (!use.empty() && served == 0 && decided.empty())
      throw std::runtime_error(
          "backend '" + (o->backend.empty() ? loaded.backend : o->backend) +
          "': its sets served no first-bounce sample of this render (every context fell back "
          "to Owen-Sobol); its sets are for other targets, bins or sample counts");
    const std::string backendWord = o->backend.empty() ? loaded.backend : o->backend;
    // One note: what the sets served and why the rest fell back, the
    // backend's own decision included; or that decision alone.
    const std::string note =
        served == 0 ? decided : fallbackNote(backendWord, servedPairs(use), prepared.note, decided);
    if (!note.empty()) std::cerr << "nuld: note: " << note << "\n";
    writeRender(o->output, image,
                renderAttributes(loaded.name, loaded.scene, s, backend->name(), seed, stats));
    std::printf("scene %s\nbackend %s\nspp %zu\nresolution %dx%d\nintegrator %s\n",
                loaded.name.c_str(),
                (word.sets == BackendSets::None ? backend->name() : word.word).c_str(), s.spp,
                s.width, s.height, toString(s.integrator).c_str());
    std::printf("seconds %.3f\nsetup_seconds %.3f\nrays %llu\nrays_per_second %.4g\n",
                stats.seconds, stats.setupSeconds, (unsigned long long)stats.rays,
                stats.raysPerSecond());
    std::printf("rejected_samples %llu\nclassic_fallbacks %llu\n",
                (unsigned long long)stats.rejectedSamples,
                (unsigned long long)stats.classicFallbacks);
    if (stats.lobeBins)
      std::printf("lobe_bins %zu\nlobe_bins_tabulated %zu\n", stats.lobeBins,
                  stats.lobeBinsTabulated);
    if (word.sets != BackendSets::None)
      std::printf("sets_made %zu\nsets_cached %zu\n", prepared.setsMade, prepared.setsCached);
    // Per pair, the first-bounce contexts the sets served and those that
    // fell back to the classic sampler; not the pairs it has no sets for.
    for (const auto &u : servedPairs(use))
      std::printf("served_%s %llu\nfell_back_%s %llu\n", u.pair.c_str(),
                  (unsigned long long)u.served, u.pair.c_str(), (unsigned long long)u.fellBack);
    return 0;
  };
}

Runner addCompare(CLI::App &app) {
  struct Options {
    std::string image, reference, errorMapPath, flipMapPath;
    FlipViewing viewing;
  };
  auto o = std::make_shared<Options>();
  app.add_option("image", o->image, "rendered image (EXR)")->required();
  app.add_option("reference", o->reference, "reference image (EXR)")->required();
  app.add_option("--error-map", o->errorMapPath,
                 "false-colour relative-error PNG (default: IMAGE_error.png)");
  app.add_option("--flip-map", o->flipMapPath,
                 "the FLIP error map as a magma-coloured PNG (default: IMAGE_flip.png)");
  app.add_option("--monitor-distance", o->viewing.monitorDistanceMeters,
                 "FLIP's viewer: metres from the monitor")
      ->capture_default_str()
      ->check(positiveNumber());
  app.add_option("--monitor-width", o->viewing.monitorWidthMeters,
                 "FLIP's viewer: the monitor's width in metres")
      ->capture_default_str()
      ->check(positiveNumber());
  app.add_option("--monitor-pixels", o->viewing.monitorWidthPixels,
                 "FLIP's viewer: the monitor's width in pixels")
      ->capture_default_str()
      ->check(positiveNumber());
  app.footer(
      "Prints 'mse VALUE', 'relmse VALUE', 'screen_mse VALUE', 'mse_winsorized VALUE' and\n"
      "'top_share VALUE' over pixels and RGB channels; relmse divides each squared error by\n"
      "(reference^2 + 0.01); screen_mse low-passes the error image by a Gaussian of 1 pixel\n"
      "(truncated at 3) before squaring: the error a viewer sees, where blue-noise error\n"
      "fades; mse_winsorized clips the largest 0.1 % of pixel errors (at least one) to the\n"
      "next largest, and top_share is their share of the squared error: near 1, a few\n"
      "fireflies are the MSE. 'flip VALUE' is the mean of NVIDIA's FLIP (Andersson et al.\n"
      "2020): HDR-FLIP (2021) for linear images, its exposures from the reference\n"
      "('flip_exposures START STOP COUNT'), LDR-FLIP for a PNG/JPEG pair; at FLIP's\n"
      "default viewer, 0.7 m from a 0.7 m wide 3840-pixel monitor (67 pixels per degree).");
  return [o] {
    // A PNG or JPEG holds tone-mapped display values (nuld render writes one
    // beside each EXR), an EXR, PFM or HDR linear radiance: their difference
    // measures the tone map, not the render.
    const auto display = [](const std::string &path) {
      return imageEncoding(path) == ImageEncoding::Display;
    };
    if (display(o->image) != display(o->reference)) {
      const std::string &png = display(o->image) ? o->image : o->reference;
      throw std::invalid_argument(
          png +
          ": a display image (tone-mapped PNG/JPEG) cannot be compared with linear "
          "radiance (" +
          (display(o->image) ? o->reference : o->image) +
          "); compare the EXR nuld render writes beside it");
    }
    if (display(o->image))
      warning(
          "comparing display values (tone-mapped, 8 bit), not radiance: use the EXRs for "
          "render error");
    const Image img = readImage(o->image, false), ref = readImage(o->reference);
    const ImageError e = compareImages(img, ref);
    std::printf("mse %.9g\nrelmse %.9g\nscreen_mse %.9g\nmse_winsorized %.9g\ntop_share %.9g\n",
                e.mse, e.relmse, e.screen, e.winsorized, e.topShare);
    if (e.nonFinitePixels) std::printf("nonfinite_pixels %zu\n", e.nonFinitePixels);
    const auto beside = [&](const std::string &given, const char *suffix) {
      // IMAGE.exr -> IMAGE_error.png, beside it
      return given.empty() ? std::filesystem::path(o->image).replace_extension().string() + suffix
                           : given;
    };
    writeImage(beside(o->errorMapPath, "_error.png"), errorMap(img, ref));
    // FLIP needs every pixel: it is left out where the image has
    // non-finite ones (refused below).
    if (!e.nonFinitePixels) {
      const FlipResult flip =
          display(o->image) ? ldrFlip(img, ref, o->viewing) : hdrFlip(img, ref, o->viewing);
      std::printf("flip %.9g\n", flip.mean);
      if (!display(o->image)) {
        const FlipExposures x = hdrFlipExposures(ref);
        std::printf("flip_exposures %.6g %.6g %d\n", x.start, x.stop, x.count);
      }
      writeImage(beside(o->flipMapPath, "_flip.png"), flipMapImage(flip));
    }
    if (e.nonFinitePixels)
      throw std::runtime_error(o->image + ": " + std::to_string(e.nonFinitePixels) +
                               " pixels are not finite (the error above leaves them out)");
    return 0;
  };
}

}  // namespace nuld::cli
