// Rendering and images for Python (tools/python/README.md): a scene with a
// backend to a float32 (H, W, 3) array, images compared and read or written.

#include <pybind11/stl.h>
#include <tbb/global_control.h>

#include <atomic>
#include <climits>
#include <cstring>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <thread>

#include "backends/backend_registry.h"
#include "backends/ready_backend.h"
#include "backends/reference_cache.h"
#include "renderer/flip.h"
#include "renderer/image_metrics.h"
#include "renderer/render.h"
#include "scenes/scene_file.h"
#include "tools/python/args.h"
#include "tools/python/bindings.h"
#include "tools/python/stream_sampler.h"

namespace nuld::python {

namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

FloatArray arrayOf(const Image &img) {
  std::vector<py::ssize_t> shape{img.height, img.width};
  if (img.channels != 1) shape.push_back(img.channels);
  FloatArray out(shape);
  std::memcpy(out.mutable_data(), img.pixels.data(), img.pixels.size() * sizeof(float));
  return out;
}

// An image array (H, W) or (H, W, C), C from 1 to 4, of real numbers; with
// `finite`, every value finite as nuld's image readers require.
Image imageOf(py::handle h, const Arg &arg, bool finite) {
  const std::string shape = "an image array of shape (H, W) or (H, W, C), C from 1 to 4";
  const FloatArray a = FloatArray::ensure(realArray(h, arg, shape + ", of real numbers"));
  if (!(a.ndim() == 2 || (a.ndim() == 3 && a.shape(2) >= 1 && a.shape(2) <= 4)) ||
      a.shape(0) == 0 || a.shape(1) == 0) {
    std::string got;
    for (py::ssize_t d = 0; d < a.ndim(); ++d) got += (d ? ", " : "") + std::to_string(a.shape(d));
    throw py::value_error(arg.function + ": " + arg.name + ": expected " + shape + ", got (" + got +
                          ")");
  }
  Image img{int(a.shape(1)), int(a.shape(0)), a.ndim() == 3 ? int(a.shape(2)) : 1, {}};
  img.pixels.assign(a.data(), a.data() + a.size());
  if (finite)
    if (const std::string why = nonFinitePixel(img); !why.empty())
      throw py::value_error(arg.function + ": " + arg.name + ": " + why);
  return img;
}

// The (width, height) of `resolution`.
std::pair<int, int> resolutionArg(py::handle h, const Arg &a) {
  const std::string expected = "a pair (width, height) of whole numbers";
  if (py::isinstance<py::str>(h) || !PySequence_Check(h.ptr()) || py::len(h) != 2)
    a.typeError(expected, h);
  const py::sequence wh = py::reinterpret_borrow<py::sequence>(h);
  return {int(wholeNumber(wh[0], {a.function, a.name + "[0]"}, 1, INT_MAX)),
          int(wholeNumber(wh[1], {a.function, a.name + "[1]"}, 1, INT_MAX))};
}

// A render's progress for Python (render's `progress`, Ctrl-C): the sets'
// making and the tiles, reported from whichever thread does the work. The
// callable is called with the GIL, at most once a permille of each stage;
// Ctrl-C is seen when the calling thread (the one Python's signal handlers
// run on) finishes a tile or a report.
class RenderProgress {
 public:
  explicit RenderProgress(const Progress &callback)
      : callback_(callback), main_(std::this_thread::get_id()) {}
  void operator()(const char *stage, long done, long total, const std::string &status) {
    const bool report = callback_ && (1000 * done / total != last_.load() || done == total);
    const bool main = std::this_thread::get_id() == main_;
    if (!report && !main) return;
    py::gil_scoped_acquire acquire;
    if (main && PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C
    if (!report) return;
    last_ = 1000 * done / total;
    py::dict d;
    d["stage"] = stage, d["done"] = done, d["total"] = total, d["status"] = status;
    callback_(d);
  }
  void nextStage() { last_ = -1; }

 private:
  const Progress &callback_;
  const std::thread::id main_;
  std::atomic<long> last_ = -1;  // the permille last reported
};

// "render: NAME applies to WHEN only", for each argument given that does not
// apply (the rules of nuld render's onlyWhen).
void onlyWhen(bool applies, std::initializer_list<std::pair<const char *, bool>> given,
              const std::string &when) {
  if (applies) return;
  for (const auto &[name, isGiven] : given)
    if (isGiven)
      throw std::invalid_argument("render: " + std::string(name) + " applies to " + when + " only");
}

// render(reference=True): the scene's reference from the reference cache,
// or rendered into it, as nuld render --reference makes it; with `stats`,
// (image, dict) with its own noise and where it came from.
py::object cachedReferenceOf(const LoadedScene &loaded, const RenderSettings &s,
                             std::optional<std::size_t> spp,
                             const std::optional<std::string> &backend,
                             std::optional<std::uint64_t> seed, bool stats,
                             const Progress &progress) {
  ReferenceSettings r;
  r.render = s;
  if (spp) r.spp = *spp;
  if (backend) r.backend = *backend;
  if (seed) r.seed = *seed;
  if (parseBackendWord(r.backend).sets != BackendSets::None)
    throw std::invalid_argument(
        "render: backend: a reference renders with a classic backend "
        "(halton, sobol, independent, ...), not '" +
        r.backend + "', whose sets would bias it");
  RenderProgress report(progress);
  CachedReference ref;
  {
    py::gil_scoped_release release;
    ref = cachedReference(loaded.scene, slug(loaded.name), r, ReferenceCache::fromEnvironment(),
                          [&](const ReferenceProgress &p) {
                            report("reference", long(1000 * p.fraction), 1000,
                                   referenceProgressText(p));
                          });
  }
  FloatArray out = arrayOf(ref.result.image);
  if (!stats) return py::object(out);
  py::dict d;
  d["backend"] = r.backend, d["spp"] = r.totalSpp(), d["integrator"] = toString(s.integrator);
  d["variance"] = ref.result.noise.variance, d["relvariance"] = ref.result.noise.relVariance;
  d["cache"] = ref.found ? "found" : "rendered";
  d["seconds"] = ref.found ? 0.0 : ref.result.seconds;
  d["made_seconds"] = ref.result.totalSeconds;
  d["entry"] = ref.dir.string();
  return py::object(py::make_tuple(out, d));
}

}  // namespace

void bindRender(py::module_ &m) {
  // Any whole number (the range is RenderOverrides::check's), and one >= 1.
  const auto anyWhole = [](py::handle h, const Arg &a) {
    return int(wholeNumber(h, a, INT_MIN, INT_MAX));
  };
  const auto positive = [](py::handle h, const Arg &a) {
    return int(wholeNumber(h, a, 1, INT_MAX));
  };
  defFunction(
      m, "render",
      {"render",
       {Param("scene", "default"),
        Param("backend", py::none()),
        Param("spp", py::none()),
        Param("resolution", py::none()),
        Param("integrator", py::none()),
        Param("max_depth", py::none()),
        Param("seed", py::none()),
        Param("assets", py::none()),
        Param("lobe_mix", py::none()),
        Param("stats", false),
        Param("opt_instances", py::none()),
        Param("opt_epochs", py::none()),
        Param("opt_lobe_epochs", py::none()),
        Param("threads", py::none()),
        Param("lobe_choice", std::string(toString(kDefaultLobeChoice))),
        Param("env_importance", py::none()),
        Param("resolution_scale", 1.0),
        Param("lobe_routes", py::none()),
        Param("lobe_defensive", py::none()),
        Param("lobe_bounces", py::none()),
        Param("opt_nested", false),
        Param("opt_objective", py::none()),
        Param("opt_union_weight", py::none()),
        Param("progress", py::none()),
        Param("sampler", py::none()),
        Param("sampler_domains", py::none()),
        Param("reference", false)}},
      [anyWhole, positive](
          py::object sceneArg, py::object backendArg, py::object sppArg, py::object resArg,
          py::object integratorArg, py::object depthArg, py::object seedArg, py::object assetsArg,
          py::object mixArg, py::object statsArg, py::object instancesArg, py::object epochsArg,
          py::object lobeEpochsArg, py::object threadsArg, py::object choiceArg,
          py::object importanceArg, py::object scaleArg, py::object routesArg,
          py::object defensiveArg, py::object bouncesArg, py::object nestedArg,
          py::object objectiveArg, py::object unionArg, py::object progressArg,
          py::object samplerArg, py::object samplerDomainsArg, py::object referenceArg) {
        const std::string f = "render";
        const std::string scene = text(sceneArg, {f, "scene"});
        const auto backend = optional(backendArg, {f, "backend"}, text);
        const auto spp =
            optional(sppArg, {f, "spp"}, [](py::handle h, const Arg &a) { return count(h, a); });
        const auto resolution = optional(resArg, {f, "resolution"}, resolutionArg);
        const auto integrator = optional(integratorArg, {f, "integrator"}, text);
        const auto maxDepth = optional(depthArg, {f, "max_depth"}, anyWhole);
        const auto seed = optional(seedArg, {f, "seed"}, python::seed);
        const auto assets = optional(assetsArg, {f, "assets"}, text);
        const auto lobeMix = optional(mixArg, {f, "lobe_mix"}, number);
        const bool stats = flag(statsArg, {f, "stats"});
        // The study's sets (--opt-*): unset, the study's defaults.
        const auto optInstances = optional(instancesArg, {f, "opt_instances"}, positive);
        const auto optEpochs = optional(epochsArg, {f, "opt_epochs"}, positive);
        const auto optLobeEpochs = optional(lobeEpochsArg, {f, "opt_lobe_epochs"}, positive);
        const bool optNested = flag(nestedArg, {f, "opt_nested"});
        const auto optObjective = optional(objectiveArg, {f, "opt_objective"}, text);
        const auto optUnion = optional(unionArg, {f, "opt_union_weight"}, number);
        const auto threads = optional(threadsArg, {f, "threads"}, positive);
        const std::string lobeChoice = text(choiceArg, {f, "lobe_choice"});
        const auto importance = optional(importanceArg, {f, "env_importance"}, text);
        const double scale = number(scaleArg, {f, "resolution_scale"});
        if (resolution && scale != 1)
          throw std::invalid_argument(
              "render: resolution_scale: not with resolution (give one of the two)");
        const auto routes = optional(routesArg, {f, "lobe_routes"}, text);
        const auto defensive = optional(defensiveArg, {f, "lobe_defensive"}, number);
        const auto bounces = optional(bouncesArg, {f, "lobe_bounces"}, anyWhole);
        const Progress progress(progressArg, {f, "progress"});
        const bool ownSampler = !samplerArg.is_none();
        const auto samplerDomains = optional(samplerDomainsArg, {f, "sampler_domains"}, positive);
        onlyWhen(ownSampler, {{"sampler_domains", bool(samplerDomains)}}, "a sampler");
        if (ownSampler && backend)
          throw std::invalid_argument(
              "render: backend: not with sampler (the domains a sampler leaves are sobol's)");
        SetSettings sets;
        if (optInstances) sets.instances = std::size_t(*optInstances);
        sets.epochs = optEpochs.value_or(0);
        sets.lobeEpochs = optLobeEpochs.value_or(0);
        sets.nested = optNested;
        if (optObjective) {
          sets.envObjective = kObjectiveNames.parse(*optObjective);
          if (sets.envObjective != Objective::SoftBoxes &&
              sets.envObjective != Objective::ExactL2asd)
            Arg{f, "opt_objective"}.valueError("'soft' or 'l2asd'", objectiveArg);
        }
        if (optUnion) {
          if (*optUnion < 0) Arg{f, "opt_union_weight"}.valueError("a weight >= 0", unionArg);
          sets.unionWeight = *optUnion;
        }
        // Cores for this call (as the CLI's --threads), released on return.
        std::optional<tbb::global_control> limit;
        if (threads) limit.emplace(tbb::global_control::max_allowed_parallelism, *threads);
        const bool builtIn = isBuiltInScene(scene);
        onlyWhen(!builtIn, {{"assets", bool(assets)}},
                 "scene files (the built-in scenes need no assets)");
        const SceneChoices choices{
            kLobeChoiceNames.parse(lobeChoice),
            importance ? std::optional(kImportanceNames.parse(*importance)) : std::nullopt};
        LoadedScene loaded = loadScene(
            scene, builtIn ? std::string() : resolveAssetRoot(assets.value_or("")), choices);
        RenderOverrides change;
        change.spp = spp;
        if (resolution) change.width = resolution->first, change.height = resolution->second;
        if (integrator) change.integrator = parseIntegrator(*integrator);
        change.maxDepth = maxDepth;
        change.resolutionScale = scale;
        change.lobeMix = lobeMix;
        if (routes) change.lobeRouting = kLobeRoutingNames.parse(*routes);
        change.lobeDefensive = defensive;
        change.lobeBounces = bounces;
        // The values, the memory the render takes and the renderer's rules,
        // as nuld render checks them.
        const RenderSettings s = change.appliedTo(loaded.settings, OverrideNames::python());
        change.checkApplicable(s, OverrideNames::python());
        const bool reference = flag(referenceArg, {f, "reference"});
        // The study's words make (or find in the set cache) their sets as
        // `nuld render` does, with the study's default --opt-* settings.
        const BackendWord word = parseBackendWord(backend ? *backend : loaded.backend);
        onlyWhen(!reference && !ownSampler && word.makesSets(),
                 {{"opt_instances", bool(optInstances)},
                  {"opt_epochs", bool(optEpochs)},
                  {"opt_lobe_epochs", bool(optLobeEpochs)},
                  {"opt_nested", optNested},
                  {"opt_objective", bool(optObjective)},
                  {"opt_union_weight", bool(optUnion)}},
                 "the study's backends that make sets (optimized, optimized-bsdf, ...)");
        // A reference samples lobes only through a backend that does
        // (sobol-tabulated); a reference's backend is refused below if it
        // makes sets.
        const bool samplesLobes = reference ? !word.makesSets() && word.samplesLobes()
                                            : !ownSampler && word.samplesLobes();
        if (lobeMix || routes || defensive || bounces)
          onlyWhen(s.integrator != IntegratorKind::Light && samplesLobes,
                   {{"lobe_mix", bool(lobeMix)},
                    {"lobe_routes", bool(routes)},
                    {"lobe_defensive", bool(defensive)},
                    {"lobe_bounces", bool(bounces)}},
                   "a backend that samples lobe tables (sobol-tabulated, lobe banks) and an "
                   "integrator other than light");
        if (reference) {
          if (ownSampler) throw std::invalid_argument("render: reference: not with sampler");
          return cachedReferenceOf(loaded, s, spp ? std::optional(std::size_t(*spp)) : std::nullopt,
                                   backend, seed, stats, progress);
        }
        const std::uint64_t seedValue = seed ? *seed : loaded.seed;
        PreparedBackend prepared;
        RenderStats st;
        Image img;
        std::unique_ptr<SamplerBackend> b;
        if (ownSampler)
          b = std::make_unique<StreamSampler>(samplerArg, std::uint32_t(samplerDomains.value_or(0)),
                                              seedValue);
        RenderProgress report(progress);
        {
          py::gil_scoped_release release;
          if (!ownSampler) {
            ReadyBackend ready = makeReadyBackend(
                word, loaded.scene, s, slug(scene), sets, seedValue, {},
                [&](const std::string &, double fraction, const std::string &status) {
                  report("sets", long(1000 * fraction), 1000, status);
                });
            prepared = std::move(ready.prepared);
            b = std::move(ready.backend);
          }
          report.nextStage();
          img = render(loaded.scene, s, *b, &st, [&](std::size_t done, std::size_t all) {
            report("render", long(done), long(all),
                   std::to_string(done) + "/" + std::to_string(all) + " tiles");
          });
        }
        FloatArray out = arrayOf(img);
        if (!stats) return py::object(out);
        py::dict d;
        d["backend"] = b->name(), d["spp"] = s.spp, d["integrator"] = toString(s.integrator);
        d["lobe_choice"] = toString(loaded.scene.lobeChoice);
        if (loaded.scene.environment)
          d["env_importance"] = toString(loaded.scene.environment->weight());
        // One setup time, as the studies count it: tables, backend and sets made.
        d["seconds"] = st.seconds, d["setup_seconds"] = st.setupSeconds + prepared.setupSeconds;
        d["rays"] = st.rays;
        d["rejected_samples"] = st.rejectedSamples, d["classic_fallbacks"] = st.classicFallbacks;
        if (!ownSampler && word.sets != BackendSets::None)
          d["backend"] = word.word, d["sets_made"] = prepared.setsMade,
          d["sets_cached"] = prepared.setsCached;
        // What `nuld render` prints as notes: lobe bins left without banks,
        // tables a model's banks did not pass.
        std::string notes = prepared.note;
        const SamplerBackend::Report sampling = b->report();
        if (const std::string &n = sampling.note; !n.empty())
          notes += (notes.empty() ? "" : "; ") + n;
        if (!notes.empty()) d["note"] = notes;
        for (const auto &u : sampling.pairUse) {
          if (u.served == 0) continue;  // a pair the backend has no sets for
          d[py::str("served_" + u.pair)] = u.served;
          d[py::str("fell_back_" + u.pair)] = u.fellBack;
        }
        return py::object(py::make_tuple(out, d));
      },
      R"(Renders a scene file (or a built-in scene: 'default', 'stress', 'cornell', 'veach-mis') as `nuld render` does, to a
linear float32 (H, W, 3) array, row 0 at the top. Unset arguments take the
scene's values; resolution is (width, height); assets (scene files only)
defaults to $NULD_ASSETS, else ../shared/assets. backend: any word `nuld
help backends` lists, the study's optimized, optimized-bsdf, ... included
(their sets made into the set cache, $NULD_CACHE, or found there; for those
only, opt_instances, opt_epochs, opt_lobe_epochs, opt_nested, opt_objective
and opt_union_weight as nuld render's --opt-*, unset: the CLI's defaults);
threads: the cores to use, default all; lobe_choice: how Disney materials
pick a lobe, 'albedo' (the default), 'weight' or 'uniform' (the paper's
configuration, with env_importance='luminance'), as --lobe-choice;
env_importance: what weighs the environment map's sampling in place of the
scene's, as --env-importance; resolution_scale, max_depth (integrator path
only), lobe_mix, lobe_routes, lobe_defensive and lobe_bounces (backends that
sample lobe tables) as --res-scale, --max-depth and the --lobe-* options.
progress: None (the default), True (a text bar on stderr) or a callable
taking a dict (stage 'sets' or 'render', done, total, status); Ctrl-C raises
KeyboardInterrupt. A render the machine cannot hold is refused before
anything is made. sampler: your own sampler in place of backend, a
scipy.stats.qmc engine of d = 2 (its random(n)) or a callable n -> (n, 2)
array of points in [0, 1)^2 (1D domains take the first column), or a
callable (n, domain) -> (n, dims) told each domain (a dict: index, role,
bounce, dimensions, integrator), drawn in blocks per batch of tiles (one
stream dealt spp samples a pixel, each pixel's shuffled per domain; the
engine advances, so pass a fresh one for a repeatable render);
sampler_domains: the first domains it serves (1: the camera's; default
every domain), the rest sobol's. With stats=True returns (image, dict), the dict with what
a learned backend's sets served per pair and, under 'note', what nuld render
prints as notes. reference=True: the scene's reference as nuld render
--reference and the studies make it (spp in all, default 4096, in passes of
two independent halves; backend default 'halton', seed default the
studies'), from the reference cache or rendered into it; its stats dict
holds its own 'variance' and 'relvariance', 'cache' ('found' or
'rendered'), 'seconds' (0 when found), 'made_seconds' and 'entry'.)");

  defFunction(
      m, "compare", {"compare", {Param("image"), Param("reference")}},
      [](py::object image, py::object reference) {
        // As nuld compare reads them: the image may hold non-finite pixels
        // (counted), the reference may not (compareImages).
        const ImageError e = compareImages(imageOf(image, {"compare", "image"}, false),
                                           imageOf(reference, {"compare", "reference"}, false));
        py::dict d;
        d["mse"] = e.mse, d["relmse"] = e.relmse, d["screen"] = e.screen;
        d["mse_winsorized"] = e.winsorized, d["top_share"] = e.topShare;
        d["nonfinite_pixels"] = e.nonFinitePixels;
        return d;
      },
      "mse, relmse, screen (the MSE of the error low-passed by a Gaussian of 1 pixel, the "
      "error a viewer sees), mse_winsorized (the largest 0.1 % of pixel errors clipped to the "
      "next largest) and top_share (their share of the squared error), as `nuld compare`, of "
      "an image against a finite reference of the same size and channels; nonfinite_pixels "
      "counts the image's pixels left out. nuld.flip gives FLIP");

  defFunction(
      m, "flip",
      {"flip",
       {Param("image"), Param("reference"), Param("display", false), Param("monitor_distance", 0.7),
        Param("monitor_width", 0.7), Param("monitor_pixels", 3840)}},
      [](py::object image, py::object reference, py::object display, py::object distance,
         py::object width, py::object pixels) {
        const Image img = imageOf(image, {"flip", "image"}, true),
                    ref = imageOf(reference, {"flip", "reference"}, true);
        FlipViewing v;
        v.monitorDistanceMeters = number(distance, {"flip", "monitor_distance"});
        v.monitorWidthMeters = number(width, {"flip", "monitor_width"});
        v.monitorWidthPixels = number(pixels, {"flip", "monitor_pixels"});
        const bool ldr = flag(display, {"flip", "display"});
        FlipResult r;
        try {
          r = ldr ? ldrFlip(img, ref, v) : hdrFlip(img, ref, v);
        } catch (const std::invalid_argument &e) {
          throw py::value_error(std::string("flip: ") + e.what());
        }
        py::dict d;
        d["mean"] = r.mean;
        Image map{r.width, r.height, 1, r.map};
        d["map"] = arrayOf(map);
        if (!ldr) {
          const FlipExposures x = hdrFlipExposures(ref);
          d["exposures"] = py::make_tuple(x.start, x.stop, x.count);
        }
        return d;
      },
      "NVIDIA's FLIP of an image against a reference, as `nuld compare` prints it: HDR-FLIP "
      "(Andersson et al. 2021) of linear images, its exposures (start, stop, count) from the "
      "reference, or with display=True LDR-FLIP (2020) of sRGB-encoded ones in [0, 1]; "
      "'mean' and the per-pixel 'map' (H, W) in [0, 1]. The viewer: monitor_distance and "
      "monitor_width in metres, monitor_pixels across (FLIP's defaults, 67 pixels per "
      "degree)");

  defFunction(
      m, "read_image", {"read_image", {Param("path")}},
      [](py::object path) {
        return arrayOf(readImage(text(path, {"read_image", "path"}), false));
      },
      "an EXR, PFM or PNG as a float32 array (H, W[, C])");
  defFunction(
      m, "read_image_attributes", {"read_image_attributes", {Param("path")}},
      [](py::object path) {
        py::dict d;
        for (const auto &[name, value] :
             readImageAttributes(text(path, {"read_image_attributes", "path"})))
          d[py::str(name)] = value;
        return d;
      },
      "the nuld:* attributes of a render's EXR or PNG (scene, backend, spp, seed, ...)");
  defFunction(
      m, "write_image", {"write_image", {Param("path"), Param("image")}},
      [](py::object path, py::object image) {
        const std::string file = text(path, {"write_image", "path"});
        writeImage(file, imageOf(image, {"write_image", "image"}, true));
      },
      "writes an image (EXR or PNG, by extension); its values must be finite, as nuld's image "
      "readers require");
}

}  // namespace nuld::python
