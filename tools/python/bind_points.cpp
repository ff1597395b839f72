// Targets, sequences, the optimizer, metrics, neural models and point-set
// files for Python (tools/python/README.md). Long work (optimize, neural
// generation) runs without the GIL; the progress callback takes it back.

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>

#include "sampler/io/pointset_io.h"
#include "sampler/metrics/discrepancy.h"
#include "sampler/neural/neural_generator.h"
#include "sampler/optimize/optimizer.h"
#include "sampler/resources.h"
#include "sampler/sequences/rng.h"
#include "sampler/sequences/sequence.h"
#include "sampler/targets/target_spec.h"
#include "tools/python/args.h"
#include "tools/python/bindings.h"

namespace nuld::python {

DoubleArray arrayOf(const std::vector<Point2> &points, std::size_t n, std::size_t instances) {
  DoubleArray out = instances == 0
                        ? DoubleArray({py::ssize_t(n), py::ssize_t(2)})
                        : DoubleArray({py::ssize_t(instances), py::ssize_t(n), py::ssize_t(2)});
  if (!points.empty())
    std::memcpy(out.mutable_data(), points.data(), points.size() * sizeof(Point2));
  return out;
}

namespace {

using TargetPtr = std::shared_ptr<Target>;

TargetPtr targetOf(const std::string &spec) { return TargetPtr(makeTarget(spec)); }

// A Target or a SPEC string; None gives nullptr.
TargetPtr targetArg(py::handle h, const Arg &a) {
  if (h.is_none()) return nullptr;
  if (py::isinstance<py::str>(h)) return targetOf(h.cast<std::string>());
  if (py::isinstance<Target>(h)) return h.cast<TargetPtr>();
  a.typeError("a nuld.Target or a SPEC string", h);
}

// Two numbers (lo, hi), a box corner or a schedule's ends.
std::pair<double, double> pairArg(py::handle h, const Arg &a) {
  const std::vector<double> v = numbers(h, a);
  if (v.size() != 2) a.valueError("two numbers", h);
  return {v[0], v[1]};
}

// One value per point of a (N, 2) or (K, N, 2) array, in the array's shape
// without its last axis.
template <class F>
DoubleArray perPoint(py::handle h, const Arg &arg, F f) {
  std::size_t n, instances;
  const std::vector<Point2> points = python::points(h, arg, n, &instances);
  std::vector<py::ssize_t> shape{py::ssize_t(n)};
  if (instances) shape.insert(shape.begin(), py::ssize_t(instances));
  DoubleArray out(shape);
  double *o = out.mutable_data();
  for (std::size_t i = 0; i < points.size(); ++i) o[i] = f(points[i]);
  return out;
}

// requireMemory for `copies` arrays of `instances` sets of n points (16
// bytes a point), before any is made: "FUNCTION: instances x n: K x N
// points needs about ...", or "n: N points" without instances.
void requirePointsMemory(const std::string &function, std::size_t n,
                         std::optional<std::size_t> instances, int copies) {
  requireMemory(double(n) * double(instances.value_or(1)) * copies * sizeof(Point2),
                function + ": " +
                    (instances ? "instances x n: " + std::to_string(*instances) + " x " : "n: ") +
                    std::to_string(n) + " points");
}

// The settings optimize takes as keywords beyond its parameters (as nuld
// optimize's options).
const std::vector<std::string> kOptimizerSettings = {
    "epochs",    "boxes",        "box_kind",    "mc_samples",    "mapping",
    "objective", "lr",           "alpha",       "ramp_fraction", "cutoff",
    "seed",      "union_weight", "union_group", "nested",        "nested_power"};

// The optimizer's settings: the preset's for (target, n), then every knob
// given.
OptimizerSettings optimizerSettingsFor(const Target &target, std::size_t n, std::size_t instances,
                                       const std::optional<std::string> &preset,
                                       const py::dict &knobs) {
  OptimizerSettings s = presetSettings(preset ? *preset : defaultPreset(target), n);
  s.instances = instances;
  s.seed = kDefaultSeed;  // the commands' one default (sampler/sequences/rng.h)
  for (const auto &[key, value] : knobs) {
    const std::string k = py::cast<std::string>(key);
    const Arg a{"optimize", k};
    if (k == "epochs")
      s.epochs = int(wholeNumber(value, a, 1, INT_MAX));
    else if (k == "boxes")
      s.boxes = count(value, a, 1);
    else if (k == "box_kind")
      s.boxKind = parseEnum<BoxKind>(text(value, a));
    else if (k == "mc_samples")
      s.mcSamples = count(value, a, 1);
    else if (k == "mapping")
      s.mapping = parseMapping(text(value, a));
    else if (k == "objective")
      s.objective = parseObjective(text(value, a));
    else if (k == "lr")
      std::tie(s.lrStart, s.lrEnd) = pairArg(value, a);
    else if (k == "alpha")
      std::tie(s.alphaStart, s.alphaEnd) = pairArg(value, a);
    else if (k == "ramp_fraction")
      s.rampFraction = number(value, a);
    else if (k == "cutoff")
      s.cutoff = number(value, a);
    else if (k == "seed")
      s.seed = seed(value, a);
    else if (k == "union_weight")
      s.unionWeight = number(value, a);
    else if (k == "union_group")
      s.unionGroup = count(value, a);
    else if (k == "nested") {  // one size: the chain m, 2m, ... below n; a list: those
      if (py::isinstance<py::int_>(value)) {
        s.nestedSizes = nestedChain(count(value, a, 1), s.n);
      } else {
        s.nestedSizes.clear();
        for (double v : numbers(value, a)) {
          if (v < 1 || v != std::floor(v)) a.valueError("a size >= 1 or a list of them", value);
          s.nestedSizes.push_back(std::size_t(v));
        }
      }
    } else if (k == "nested_power")
      s.nestedPower = number(value, a);
    else  // Signature::bind passes only kOptimizerSettings
      throw py::type_error(unknownKeyword("optimize", k, kOptimizerSettings));
  }
  s.validate();
  return s;
}

}  // namespace

void bindPoints(py::module_ &m) {
  py::class_<Target, TargetPtr> target(m, "Target", R"(A density on the unit square (or the sphere
through the equal-area map), made from the same SPEC strings as the CLI's
--target (`nuld help targets`).)");
  const Signature init{"Target", {Param("spec")}};
  target.def(py::init([init](py::args args, py::kwargs kwargs) {
               return named("Target", [&] {
                 return targetOf(text(init.bind(args, kwargs)[0], {"Target", "spec"}));
               });
             }),
             init.docstring("__init__", "a target from its SPEC string", true).c_str());
  target.def_property_readonly("spec", &Target::spec, "the SPEC string that rebuilds it")
      .def_property_readonly("domain", [](const Target &t) { return toString(t.domain()); })
      .def_property_readonly("is_uniform", &Target::isUniform)
      .def("__repr__", [](const Target &t) { return "nuld.Target('" + t.spec() + "')"; });
  defMethod(
      target, "pdf", {"Target.pdf", {Param("points")}},
      [](const Target &t, py::object x) {
        return perPoint(x, {"Target.pdf", "points"}, [&](Point2 p) { return t.pdf(p); });
      },
      "density at each point of an (N, 2) or (K, N, 2) array");
  defMethod(
      target, "mass", {"Target.mass", {Param("lo"), Param("hi")}},
      [](const Target &t, py::object lo, py::object hi) {
        const auto [x0, y0] = pairArg(lo, {"Target.mass", "lo"});
        const auto [x1, y1] = pairArg(hi, {"Target.mass", "hi"});
        return t.mass({{x0, y0}, {x1, y1}});
      },
      "exact probability of the box [lo, hi)");
  defMethod(
      target, "invert", {"Target.invert", {Param("u")}},
      [](const Target &t, py::object u) {
        if (!t.hasInverse())
          throw std::invalid_argument("Target.invert: '" + t.spec() + "' has no inverse-CDF map");
        std::size_t n, instances;
        std::vector<Point2> p = points(u, {"Target.invert", "u"}, n, &instances);
        for (Point2 &q : p) q = t.invert(q).x;
        return arrayOf(p, n, instances);
      },
      "the inverse-CDF map of uniform points u in [0, 1)^2");
  // A SPEC string wherever a Target is expected.
  py::implicitly_convertible<py::str, Target>();

  defFunction(
      m, "sequence",
      {"sequence",
       {Param("n"), Param("kind", "sobol"), Param("scramble", py::none()),
        Param("seed", kDefaultSeed), Param("instances", py::none()), Param("target", py::none())}},
      [](py::object n, py::object kind, py::object scramble, py::object seedArg,
         py::object instances, py::object target) {
        const std::string f = "sequence";
        const std::size_t size = count(n, {f, "n"}, 1);
        const auto k = optional(instances, {f, "instances"},
                                [](py::handle h, const Arg &a) { return count(h, a, 1); });
        const TargetPtr t = targetArg(target, {f, "target"});
        const SequenceKind sequence = parseSequenceKind(text(kind, {f, "kind"}));
        SequenceOptions o{sequence,
                          scramble.is_none() ? defaultScramble(sequence)
                                             : parseScramble(text(scramble, {f, "scramble"})),
                          seed(seedArg, {f, "seed"})};
        requirePointsMemory(f, size, k, 2);  // the set and the array it is returned as
        PointSet set = generatePointSet(o, size, k.value_or(1));
        if (t)
          for (Point2 &p : set.points) p = t->invert(p).x;
        return arrayOf(set.points, size, k ? *k : 0);
      },
      R"(N points of a sequence (sobol, halton, random, pmj02) or set of N
(stratified, lattice), randomized by `scramble` (owen, shift, cp, baker
(lattice only: cp, then the baker's transform), none; default: the kind's
own, as nuld generate: owen, cp for lattice, none for stratified); `instances` independent randomizations as (K, N, 2); mapped
through `target`'s inverse CDF when given. `seed` defaults to 1, as every
command's.)");

  m.attr("_optimize_settings") = py::tuple(py::cast(kOptimizerSettings));
  defFunction(
      m, "optimize",
      {"optimize",
       {Param("target"), Param("n"), Param("instances", 1), Param("preset", py::none()),
        Param("progress", py::none())},
       kOptimizerSettings},
      [](py::object target, py::object nArg, py::object instancesArg, py::object presetArg,
         py::object progressArg, const py::dict &knobs) {
        const std::string f = "optimize";
        const TargetPtr t = targetArg(target, {f, "target"});
        if (!t) Arg{f, "target"}.typeError("a nuld.Target or a SPEC string", target);
        const std::size_t n = count(nArg, {f, "n"}, 1);
        const std::size_t instances = count(instancesArg, {f, "instances"}, 1);
        const auto preset = optional(presetArg, {f, "preset"}, text);
        const Progress progress(progressArg, {f, "progress"});
        const OptimizerSettings s = optimizerSettingsFor(*t, n, instances, preset, knobs);
        // At least the sets and the array they are returned as, before the
        // optimizer takes its state: a size no machine holds (or whose
        // count overflows) is refused here.
        requirePointsMemory(f, n, instances, 2);
        const DirectOptimizer opt(*t, s);
        OptimizerState state = opt.initialState();
        struct Stop {};  // the callback returned False
        try {
          py::gil_scoped_release release;
          opt.run(state, s.epochs, [&](const EpochReport &r) {
            py::gil_scoped_acquire acquire;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C
            if (!progress) return;
            py::dict d;
            d["epoch"] = r.epoch, d["epochs"] = r.epochs, d["loss"] = r.loss;
            d["alpha"] = r.alpha, d["lr"] = r.lr;
            if (!progress(d)) throw Stop{};
          });
        } catch (const Stop &) {
          // The sets as they are after the last epoch run.
        }
        return arrayOf(opt.points(state).points, n, instances);
      },
      R"(Optimizes `instances` sets of `n` points for `target` (a Target or a SPEC
string), as `nuld optimize`: the preset's settings (default: the target's
own preset), then any of epochs, boxes, box_kind, mc_samples, mapping,
objective, lr=(start, end), alpha=(start, end), ramp_fraction, cutoff, seed,
union_weight, union_group, nested (nested sets: every power-of-2 prefix from
this size on is optimized as a set too), nested_power.

progress: None, True (a text bar on stderr with ETA and loss) or a callable
taking a dict (epoch, epochs, loss, alpha, lr) after each epoch; returning
False stops there. Ctrl-C raises KeyboardInterrupt. Returns (K, N, 2).)");

  defFunction(
      m, "discrepancy",
      {"discrepancy",
       {Param("points"), Param("metric", "l2star"), Param("target", py::none()),
        Param("grid", 256)}},
      [](py::object pointsArg, py::object metricArg, py::object target, py::object gridArg) {
        const std::string f = "discrepancy";
        std::size_t n, instances;
        const std::vector<Point2> p = points(pointsArg, {f, "points"}, n, &instances);
        const std::string metric = text(metricArg, {f, "metric"});
        const TargetPtr given = targetArg(target, {f, "target"});
        const TargetPtr t = given ? given : targetOf("uniform");
        // The range nuld eval's --grid takes.
        const int grid = int(wholeNumber(gridArg, {f, "grid"}, 1, 4096));
        const std::size_t k = p.size() / n;
        std::vector<double> values(k);
        {
          py::gil_scoped_release release;
          for (std::size_t i = 0; i < k; ++i)
            values[i] =
                discrepancyByName(metric, std::span<const Point2>(p).subspan(i * n, n), *t, grid);
        }
        if (instances == 0) return py::object(py::float_(values[0]));
        DoubleArray out{py::ssize_t(k)};
        std::copy(values.begin(), values.end(), out.mutable_data());
        return py::object(out);
      },
      R"(Discrepancy of each instance (plain, not squared), as `nuld eval`:
l2star, l2asd, dstar, l2 (grid L2asd), l2per (uniform only). A scalar for
(N, 2), an array of K for (K, N, 2).)");

  defFunction(
      m, "read_points", {"read_points", {Param("path")}},
      [](py::object path) {
        const PointSet set = readPointSet(text(path, {"read_points", "path"}));
        return py::make_tuple(arrayOf(set.points, set.n, set.instances()), set.metadata);
      },
      "(points (K, N, 2), metadata dict) of a point-set file (text or binary)");
  defFunction(
      m, "write_points",
      {"write_points", {Param("path"), Param("points"), Param("metadata", py::none())}},
      [](py::object path, py::object pointsArg, py::object metadata) {
        const std::string f = "write_points";
        const std::string file = text(path, {f, "path"});
        // The format by the name's extension: a point-set file (text or
        // binary, with the metadata), or the points alone as nuld export
        // writes them.
        const std::string ext = std::filesystem::path(file).extension().string();
        const bool pointSet = ext == ".txt" || ext == ".ptsb";
        if (!pointSet && ext != ".npy" && ext != ".csv" && ext != ".dat")
          throw std::invalid_argument(
              f + ": path: '" + file +
              "': expected a name ending in .txt (text) or .ptsb (binary), point-set files "
              "nuld reads, or .npy (numpy.load), .csv or .dat (UTK), the points alone as nuld "
              "export writes them");
        PointSet set;
        set.points = points(pointsArg, {f, "points"}, set.n);
        if (!metadata.is_none()) {
          if (!py::isinstance<py::dict>(metadata))
            Arg{f, "metadata"}.typeError("a dict of str to str", metadata);
          for (const auto &[key, value] : metadata.cast<py::dict>())
            set.metadata[text(key, {f, "metadata key"})] = text(value, {f, "metadata value"});
          if (!pointSet && !set.metadata.empty())
            throw std::invalid_argument(f + ": metadata: a " + ext +
                                        " file holds the points alone; write a .txt or .ptsb "
                                        "file to keep the metadata");
        }
        if (pointSet)
          writePointSet(file, set);
        else
          exportPointSet(file, set);
      },
      R"(Writes points by the name's extension, atomically: .txt (text, UTK-compatible)
or .ptsb (binary), point-set files with the metadata; .npy (numpy.load gives
(K, N, 2)), .csv (instance,x,y) or .dat (UTK's sets separated by '#'), the
points alone, as nuld export writes them. Another extension is refused.)");

  defFunction(
      m, "generate_neural",
      {"generate_neural",
       {Param("model"), Param("instances", 1), Param("seed", kDefaultSeed),
        Param("gamma", py::tuple()), Param("n", py::none())}},
      [](py::object modelArg, py::object instancesArg, py::object seedArg, py::object gammaArg,
         py::object nArg) {
        const std::string f = "generate_neural";
        const std::string model = text(modelArg, {f, "model"});
        const std::size_t instances = count(instancesArg, {f, "instances"}, 1);
        const std::uint64_t s = seed(seedArg, {f, "seed"});
        const std::vector<double> gamma =
            gammaArg.is_none() ? std::vector<double>{} : numbers(gammaArg, {f, "gamma"});
        const auto n =
            optional(nArg, {f, "n"}, [](py::handle h, const Arg &a) { return count(h, a, 1); });
        // The network (and LibTorch, a second to load) once the sizes pass.
        const NeuralGenerator gen =
            NeuralGenerator::load(model, NeuralGenerator::NetworkLoad::OnFirstUse);
        // The family checks gamma (and the generator the size) itself.
        const std::string spec = gen.family().target(gamma)->spec();
        const std::size_t size = n.value_or(gen.settings().n);
        gen.checkSize(size);
        // The sets, the network's raw points and the array returned.
        requirePointsMemory(f, size, instances, 3);
        PointSet set;
        {
          py::gil_scoped_release release;
          set = gen.generateSets(instances, s, gamma, size);
        }
        return py::make_tuple(arrayOf(set.points, set.n, instances), spec);
      },
      "(points (K, N, 2), target spec) of K sets a trained model (nuld train) generates");
}

}  // namespace nuld::python
