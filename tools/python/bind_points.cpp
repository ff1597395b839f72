// Targets, sequences, the optimizer, metrics, neural models and point-set
// files for Python (tools/python/README.md). Long work (optimize, neural
// generation) runs without the GIL; the progress callback takes it back.

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>

#include "sampler/io/pointset_io.h"
#include "sampler/metrics/discrepancy.h"
#include "sampler/neural/neural_generator.h"
#include "sampler/optimize/optimizer.h"
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

// The optimizer's settings: the preset's for (target, n), then every knob
// given.
OptimizerSettings optimizerSettingsFor(const Target &target, std::size_t n, std::size_t instances,
                                       const std::optional<std::string> &preset,
                                       const py::kwargs &knobs) {
  OptimizerSettings s = presetSettings(preset ? *preset : defaultPreset(target), n);
  s.instances = instances;
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
    else
      throw std::invalid_argument(
          "optimize: unknown setting '" + k +
          "' (expected epochs, boxes, box_kind, mc_samples, mapping, objective, lr, alpha, "
          "ramp_fraction, cutoff, seed, union_weight, union_group, nested, nested_power)");
  }
  s.validate();
  return s;
}

}  // namespace

void bindPoints(py::module_ &m) {
  py::class_<Target, TargetPtr>(m, "Target", R"(A density on the unit square (or the sphere
through the equal-area map), made from the same SPEC strings as the CLI's
--target (`nuld help targets`).)")
      .def(py::init([](py::object spec) {
             return targetOf(text(spec, {"Target", "spec"}));
           }),
           py::arg("spec"))
      .def_property_readonly("spec", &Target::spec, "the SPEC string that rebuilds it")
      .def_property_readonly("domain", [](const Target &t) { return toString(t.domain()); })
      .def_property_readonly("is_uniform", &Target::isUniform)
      .def(
          "pdf",
          [](const Target &t, py::object x) {
            return perPoint(x, {"Target.pdf", "points"}, [&](Point2 p) { return t.pdf(p); });
          },
          py::arg("points"), "density at each point of an (N, 2) or (K, N, 2) array")
      .def(
          "mass",
          [](const Target &t, py::object lo, py::object hi) {
            const auto [x0, y0] = pairArg(lo, {"Target.mass", "lo"});
            const auto [x1, y1] = pairArg(hi, {"Target.mass", "hi"});
            return t.mass({{x0, y0}, {x1, y1}});
          },
          py::arg("lo"), py::arg("hi"), "exact probability of the box [lo, hi)")
      .def(
          "invert",
          [](const Target &t, py::object u) {
            if (!t.hasInverse())
              throw std::invalid_argument("Target.invert: '" + t.spec() +
                                          "' has no inverse-CDF map");
            std::size_t n, instances;
            std::vector<Point2> p = points(u, {"Target.invert", "u"}, n, &instances);
            for (Point2 &q : p) q = t.invert(q).x;
            return arrayOf(p, n, instances);
          },
          py::arg("u"), "the inverse-CDF map of uniform points u in [0, 1)^2")
      .def("__repr__", [](const Target &t) { return "nuld.Target('" + t.spec() + "')"; });
  // A SPEC string wherever a Target is expected.
  py::implicitly_convertible<py::str, Target>();

  m.def(
      "sequence",
      [](py::object n, py::object kind, py::object scramble, py::object seedArg,
         py::object instances, py::object target) {
        const std::string f = "sequence";
        const std::size_t size = count(n, {f, "n"}, 1);
        const auto k = optional(instances, {f, "instances"},
                                [](py::handle h, const Arg &a) { return count(h, a, 1); });
        const TargetPtr t = targetArg(target, {f, "target"});
        SequenceOptions o{parseSequenceKind(text(kind, {f, "kind"})),
                          parseScramble(text(scramble, {f, "scramble"})),
                          seed(seedArg, {f, "seed"})};
        PointSet set = generatePointSet(o, size, k.value_or(1));
        if (t)
          for (Point2 &p : set.points) p = t->invert(p).x;
        return arrayOf(set.points, size, k ? *k : 0);
      },
      py::arg("n"), py::arg("kind") = "sobol", py::arg("scramble") = "owen", py::arg("seed") = 0,
      py::arg("instances") = py::none(), py::arg("target") = py::none(),
      R"(N points of a sequence (sobol, halton, random), scrambled (owen, shift, cp,
none); `instances` independent scramblings as (K, N, 2); mapped through
`target`'s inverse CDF when given.)");

  m.def(
      "optimize",
      [](py::object target, py::object nArg, py::object instancesArg, py::object presetArg,
         py::object progress, const py::kwargs &knobs) {
        const std::string f = "optimize";
        const TargetPtr t = targetArg(target, {f, "target"});
        if (!t) Arg{f, "target"}.typeError("a nuld.Target or a SPEC string", target);
        const std::size_t n = count(nArg, {f, "n"}, 1);
        const std::size_t instances = count(instancesArg, {f, "instances"}, 1);
        const auto preset = optional(presetArg, {f, "preset"}, text);
        if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
          Arg{f, "progress"}.typeError("None, True or a callable", progress);
        const OptimizerSettings s = optimizerSettingsFor(*t, n, instances, preset, knobs);
        const DirectOptimizer opt(*t, s);
        OptimizerState state = opt.initialState();
        struct Stop {};  // the callback returned False
        try {
          py::gil_scoped_release release;
          opt.run(state, s.epochs, [&](const EpochReport &r) {
            py::gil_scoped_acquire acquire;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C
            if (progress.is_none()) return;
            py::dict d;
            d["epoch"] = r.epoch, d["epochs"] = r.epochs, d["loss"] = r.loss;
            d["alpha"] = r.alpha, d["lr"] = r.lr;
            const py::object answer = progress(d);
            if (!answer.is_none() && !answer.cast<bool>()) throw Stop{};
          });
        } catch (const Stop &) {
          // The sets as they are after the last epoch run.
        }
        return arrayOf(opt.points(state).points, n, instances);
      },
      py::arg("target"), py::arg("n"), py::arg("instances") = 1, py::arg("preset") = py::none(),
      py::arg("progress") = py::none(),
      R"(Optimizes `instances` sets of `n` points for `target` (nuld optimize):
the preset's settings (default: the target's preset), then any of epochs,
boxes, box_kind, mc_samples, mapping, objective, lr=(start, end),
alpha=(start, end), ramp_fraction, cutoff, seed, union_weight, union_group, nested (the
first prefix size of nested sets), nested_power.
`progress(dict)` is called after each epoch (epoch, epochs, loss, alpha, lr);
returning False stops there. Returns (K, N, 2).)");

  m.def(
      "discrepancy",
      [](py::object pointsArg, py::object metricArg, py::object target, py::object gridArg) {
        const std::string f = "discrepancy";
        std::size_t n, instances;
        const std::vector<Point2> p = points(pointsArg, {f, "points"}, n, &instances);
        const std::string metric = text(metricArg, {f, "metric"});
        const TargetPtr given = targetArg(target, {f, "target"});
        const TargetPtr t = given ? given : targetOf("uniform");
        const int grid = int(wholeNumber(gridArg, {f, "grid"}, 1, INT_MAX));
        const std::size_t k = p.size() / n;
        std::vector<double> values(k);
        try {
          py::gil_scoped_release release;
          for (std::size_t i = 0; i < k; ++i)
            values[i] =
                discrepancyByName(metric, std::span<const Point2>(p).subspan(i * n, n), *t, grid);
        } catch (const std::invalid_argument &e) {
          throw std::invalid_argument(std::string("discrepancy: ") + e.what());
        }
        if (instances == 0) return py::object(py::float_(values[0]));
        DoubleArray out{py::ssize_t(k)};
        std::copy(values.begin(), values.end(), out.mutable_data());
        return py::object(out);
      },
      py::arg("points"), py::arg("metric") = "l2star", py::arg("target") = py::none(),
      py::arg("grid") = 256,
      R"(Discrepancy of each instance (plain, not squared), as `nuld eval`:
l2star, l2asd, dstar, l2 (grid L2asd), l2per (uniform only). A scalar for
(N, 2), an array of K for (K, N, 2).)");

  m.def(
      "read_points",
      [](py::object path) {
        const PointSet set = readPointSet(text(path, {"read_points", "path"}));
        return py::make_tuple(arrayOf(set.points, set.n, set.instances()), set.metadata);
      },
      py::arg("path"), "(points (K, N, 2), metadata dict) of a point-set file (text or binary)");
  m.def(
      "write_points",
      [](py::object path, py::object pointsArg, py::object metadata) {
        const std::string f = "write_points";
        const std::string file = text(path, {f, "path"});
        PointSet set;
        set.points = points(pointsArg, {f, "points"}, set.n);
        if (!metadata.is_none()) {
          if (!py::isinstance<py::dict>(metadata))
            Arg{f, "metadata"}.typeError("a dict of str to str", metadata);
          for (const auto &[key, value] : metadata.cast<py::dict>())
            set.metadata[text(key, {f, "metadata key"})] = text(value, {f, "metadata value"});
        }
        writePointSet(file, set);
      },
      py::arg("path"), py::arg("points"), py::arg("metadata") = py::none(),
      "writes a point-set file (binary for .ptsb, else text), atomically");

  m.def(
      "generate_neural",
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
        const NeuralGenerator gen = NeuralGenerator::load(model);
        // The family checks gamma (and the generator the size) itself.
        const std::string spec = gen.family().target(gamma)->spec();
        PointSet set;
        {
          py::gil_scoped_release release;
          set = gen.generateSets(instances, s, gamma, n.value_or(0));
        }
        return py::make_tuple(arrayOf(set.points, set.n, instances), spec);
      },
      py::arg("model"), py::arg("instances") = 1, py::arg("seed") = 0,
      py::arg("gamma") = py::tuple(), py::arg("n") = py::none(),
      "(points (K, N, 2), target spec) of K sets a trained model (nuld train) generates");
}

}  // namespace nuld::python
