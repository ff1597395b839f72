// Rendering and images for Python (tools/python/README.md): a scene with a
// backend to a float32 (H, W, 3) array, images compared and read or written.

#include <pybind11/stl.h>
#include <tbb/global_control.h>

#include <cstring>
#include <optional>
#include <stdexcept>

#include "renderer/backend_registry.h"
#include "renderer/image_metrics.h"
#include "renderer/render.h"
#include "scenes/scene_file.h"
#include "tools/python/args.h"
#include "tools/python/bindings.h"
#include "tools/study/render_study.h"

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

Image imageOf(py::handle h, const Arg &arg) {
  const std::string what = arg.function + ": " + arg.name;
  if (h.is_none() || py::isinstance<py::str>(h)) arg.typeError("an image array of numbers", h);
  const FloatArray a = FloatArray::ensure(h);
  if (!a) arg.typeError("an image array of numbers", h);
  if (!(a.ndim() == 2 || (a.ndim() == 3 && a.shape(2) >= 1 && a.shape(2) <= 4)) ||
      a.shape(0) == 0 || a.shape(1) == 0)
    throw std::invalid_argument(what +
                                ": expected an image array of shape (H, W) or (H, W, C), "
                                "C from 1 to 4");
  Image img{int(a.shape(1)), int(a.shape(0)), a.ndim() == 3 ? int(a.shape(2)) : 1, {}};
  img.pixels.assign(a.data(), a.data() + a.size());
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

}  // namespace

void bindRender(py::module_ &m) {
  m.def(
      "render",
      [](py::object sceneArg, py::object backendArg, py::object sppArg, py::object resArg,
         py::object integratorArg, py::object depthArg, py::object seedArg, py::object assetsArg,
         py::object mixArg, py::object statsArg, py::object instancesArg, py::object epochsArg,
         py::object lobeEpochsArg, py::object threadsArg, py::object choiceArg,
         py::object importanceArg, py::object scaleArg, py::object routesArg,
         py::object defensiveArg, py::object bouncesArg) {
        const std::string f = "render";
        const std::string scene = text(sceneArg, {f, "scene"});
        const auto backend = optional(backendArg, {f, "backend"}, text);
        const auto spp =
            optional(sppArg, {f, "spp"}, [](py::handle h, const Arg &a) { return count(h, a); });
        const auto resolution = optional(resArg, {f, "resolution"}, resolutionArg);
        const auto integrator = optional(integratorArg, {f, "integrator"}, text);
        const auto maxDepth = optional(depthArg, {f, "max_depth"}, [](py::handle h, const Arg &a) {
          return int(wholeNumber(h, a, INT_MIN, INT_MAX));
        });
        const auto seed = optional(seedArg, {f, "seed"}, python::seed);
        const std::string assets = text(assetsArg, {f, "assets"});
        const auto lobeMix = optional(mixArg, {f, "lobe_mix"}, number);
        const bool stats = flag(statsArg, {f, "stats"});
        const std::size_t optInstances = count(instancesArg, {f, "opt_instances"});
        const int optEpochs = int(wholeNumber(epochsArg, {f, "opt_epochs"}, 0, INT_MAX));
        const int optLobeEpochs =
            int(wholeNumber(lobeEpochsArg, {f, "opt_lobe_epochs"}, 0, INT_MAX));
        const auto threads = optional(threadsArg, {f, "threads"}, [](py::handle h, const Arg &a) {
          return int(wholeNumber(h, a, 1, INT_MAX));
        });
        const std::string lobeChoice = text(choiceArg, {f, "lobe_choice"});
        const auto importance = optional(importanceArg, {f, "env_importance"}, text);
        const double scale = number(scaleArg, {f, "resolution_scale"});
        if (resolution && scale != 1)
          throw std::invalid_argument(
              "render: resolution_scale: not with resolution (give one of the two)");
        const auto routes = optional(routesArg, {f, "lobe_routes"}, text);
        const auto defensive = optional(defensiveArg, {f, "lobe_defensive"}, number);
        const auto bounces = optional(
            bouncesArg, {f, "lobe_bounces"},
            [](py::handle h, const Arg &a) { return int(wholeNumber(h, a, INT_MIN, INT_MAX)); });
        // Cores for this call (as the CLI's --threads), released on return.
        std::optional<tbb::global_control> limit;
        if (threads) limit.emplace(tbb::global_control::max_allowed_parallelism, *threads);
        const bool builtIn = isBuiltInScene(scene);
        const SceneChoices choices{
            kLobeChoiceNames.parse(lobeChoice),
            importance ? std::optional(kImportanceNames.parse(*importance)) : std::nullopt};
        LoadedScene loaded =
            loadScene(scene, builtIn ? std::string() : resolveAssetRoot(assets), choices);
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
        const RenderSettings s = change.appliedTo(loaded.settings, OverrideNames::python());
        const std::uint64_t seedValue = seed ? *seed : loaded.seed;
        // The study's words make (or find in the set cache) their sets as
        // `nuld render` does, with the study's default --opt-* settings.
        const study::StudyBackend word =
            study::parseStudyBackend(backend ? *backend : loaded.backend);
        study::SetSettings sets;
        sets.instances = optInstances;
        sets.epochs = optEpochs;
        sets.lobeEpochs = optLobeEpochs;
        study::PreparedBackend prepared;
        RenderStats st;
        Image img;
        std::unique_ptr<SamplerBackend> b;
        {
          py::gil_scoped_release release;
          prepared = study::prepareStudyBackend(word, loaded.scene, s, study::slug(scene), sets,
                                                seedValue);
          b = makeBackend(prepared.spec, seedValue);
          img = render(loaded.scene, s, *b, &st);
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
        if (word.sets != BackendSets::None)
          d["backend"] = word.word, d["sets_made"] = prepared.setsMade,
          d["sets_cached"] = prepared.setsCached;
        // What `nuld render` prints as notes: lobe bins left without banks,
        // tables a model's banks did not pass.
        std::string notes = prepared.note;
        if (const std::string n = b->note(); !n.empty()) notes += (notes.empty() ? "" : "; ") + n;
        if (!notes.empty()) d["note"] = notes;
        for (const auto &u : b->pairUse()) {
          if (u.served == 0) continue;  // a pair the backend has no sets for
          d[py::str("served_" + u.pair)] = u.served;
          d[py::str("fell_back_" + u.pair)] = u.fellBack;
        }
        return py::object(py::make_tuple(out, d));
      },
      py::arg("scene") = "default", py::arg("backend") = py::none(), py::arg("spp") = py::none(),
      py::arg("resolution") = py::none(), py::arg("integrator") = py::none(),
      py::arg("max_depth") = py::none(), py::arg("seed") = py::none(), py::arg("assets") = "",
      py::arg("lobe_mix") = py::none(), py::arg("stats") = false, py::arg("opt_instances") = 16,
      py::arg("opt_epochs") = 0, py::arg("opt_lobe_epochs") = 0, py::arg("threads") = py::none(),
      py::arg("lobe_choice") = std::string(toString(kDefaultLobeChoice)),
      py::arg("env_importance") = py::none(), py::arg("resolution_scale") = 1.0,
      py::arg("lobe_routes") = py::none(), py::arg("lobe_defensive") = py::none(),
      py::arg("lobe_bounces") = py::none(),
      R"(Renders a scene file (or 'default', 'stress') as `nuld render` does, to a
linear float32 (H, W, 3) array, row 0 at the top. Unset arguments take the
scene's values; resolution is (width, height); assets defaults to
$NULD_ASSETS, else ../shared/assets. backend: any word `nuld help backends`
lists, the study's optimized, optimized-bsdf, ... included (their sets made
into the set cache, $NULD_CACHE, or found there; opt_instances, opt_epochs and
opt_lobe_epochs as nuld render's --opt-*, 0 for the defaults; threads: the cores to
use, default all; lobe_choice: how Disney materials pick a lobe, 'albedo' (the
default), 'weight' or 'uniform' (the paper's configuration, with
env_importance='luminance'), as --lobe-choice; env_importance: what weighs the
environment map's sampling in place of the scene's, as --env-importance;
resolution_scale, lobe_mix, lobe_routes, lobe_defensive and lobe_bounces as
--res-scale and the --lobe-* options). With stats=True returns
(image, dict), the dict with what a learned backend's sets served per pair and,
under 'note', what nuld render prints as notes.)");

  m.def(
      "compare",
      [](py::object image, py::object reference) {
        const ImageError e = compareImages(imageOf(image, {"compare", "image"}),
                                           imageOf(reference, {"compare", "reference"}));
        py::dict d;
        d["mse"] = e.mse, d["relmse"] = e.relmse, d["nonfinite_pixels"] = e.nonFinitePixels;
        return d;
      },
      py::arg("image"), py::arg("reference"),
      "mse and relmse (as `nuld compare`) of an image against a reference of the same size");

  m.def(
      "read_image",
      [](py::object path) {
        return arrayOf(readImage(text(path, {"read_image", "path"}), false));
      },
      py::arg("path"), "an EXR, PFM or PNG as a float32 array (H, W[, C])");
  m.def(
      "read_image_attributes",
      [](py::object path) {
        py::dict d;
        for (const auto &[name, value] :
             readImageAttributes(text(path, {"read_image_attributes", "path"})))
          d[py::str(name)] = value;
        return d;
      },
      py::arg("path"),
      "the nuld:* attributes of a render's EXR or PNG (scene, backend, spp, seed, ...)");
  m.def(
      "write_image",
      [](py::object path, py::object image) {
        const std::string file = text(path, {"write_image", "path"});
        writeImage(file, imageOf(image, {"write_image", "image"}));
      },
      py::arg("path"), py::arg("image"), "writes an image (EXR, PFM or PNG by extension)");
}

}  // namespace nuld::python
