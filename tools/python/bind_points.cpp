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
#include "tools/python/bindings.h"

namespace nuld::python {

std::vector<Point2> pointsOf(const DoubleArray &a, const std::string &what, std::size_t &n) {
  static_assert(sizeof(Point2) == 2 * sizeof(double));
  const bool set = a.ndim() == 2 && a.shape(1) == 2;
  const bool bank = a.ndim() == 3 && a.shape(2) == 2;
  if (!set && !bank) {
    std::string shape;
    for (py::ssize_t d = 0; d < a.ndim(); ++d)
      shape += (d ? ", " : "") + std::to_string(a.shape(d));
    throw std::invalid_argument(what + ": expected an array of shape (N, 2) or (K, N, 2), got (" +
                                shape + ")");
  }
  n = std::size_t(set ? a.shape(0) : a.shape(1));
  std::vector<Point2> points(std::size_t(a.size()) / 2);
  if (!points.empty())
    std::memcpy(static_cast<void *>(points.data()), a.data(), points.size() * sizeof(Point2));
  return points;
}

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

// One value per point of a (N, 2) or (K, N, 2) array, in the array's shape
// without its last axis.
template <class F>
DoubleArray perPoint(const DoubleArray &a, const std::string &what, F f) {
  std::size_t n;
  const std::vector<Point2> points = pointsOf(a, what, n);
  std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim() - 1);
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
    if (k == "epochs")
      s.epochs = value.cast<int>();
    else if (k == "boxes")
      s.boxes = value.cast<std::size_t>();
    else if (k == "box_kind")
      s.boxKind = parseEnum<BoxKind>(value.cast<std::string>());
    else if (k == "mc_samples")
      s.mcSamples = value.cast<std::size_t>();
    else if (k == "mapping")
      s.mapping = parseMapping(value.cast<std::string>());
    else if (k == "objective")
      s.objective = parseObjective(value.cast<std::string>());
    else if (k == "lr")
      std::tie(s.lrStart, s.lrEnd) = value.cast<std::pair<double, double>>();
    else if (k == "alpha")
      std::tie(s.alphaStart, s.alphaEnd) = value.cast<std::pair<double, double>>();
    else if (k == "ramp_fraction")
      s.rampFraction = value.cast<double>();
    else if (k == "cutoff")
      s.cutoff = value.cast<double>();
    else if (k == "seed")
      s.seed = value.cast<std::uint64_t>();
    else if (k == "union_weight")
      s.unionWeight = value.cast<double>();
    else if (k == "union_group")
      s.unionGroup = value.cast<std::size_t>();
    else if (k == "nested")  // one size: the chain m, 2m, ... below n; a list: those
      s.nestedSizes = py::isinstance<py::int_>(value) ? nestedChain(value.cast<std::size_t>(), s.n)
                                                      : value.cast<std::vector<std::size_t>>();
    else if (k == "nested_power")
      s.nestedPower = value.cast<double>();
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
      .def(py::init(&targetOf), py::arg("spec"))
      .def_property_readonly("spec", &Target::spec, "the SPEC string that rebuilds it")
      .def_property_readonly("domain", [](const Target &t) { return toString(t.domain()); })
      .def_property_readonly("is_uniform", &Target::isUniform)
      .def(
          "pdf",
          [](const Target &t, const DoubleArray &x) {
            return perPoint(x, "Target.pdf", [&](Point2 p) { return t.pdf(p); });
          },
          py::arg("points"), "density at each point of an (N, 2) or (K, N, 2) array")
      .def(
          "mass",
          [](const Target &t, std::pair<double, double> lo, std::pair<double, double> hi) {
            return t.mass({{lo.first, lo.second}, {hi.first, hi.second}});
          },
          py::arg("lo"), py::arg("hi"), "exact probability of the box [lo, hi)")
      .def(
          "invert",
          [](const Target &t, const DoubleArray &u) {
            if (!t.hasInverse())
              throw std::invalid_argument("Target.invert: '" + t.spec() +
                                          "' has no inverse-CDF map");
            std::size_t n;
            std::vector<Point2> p = pointsOf(u, "Target.invert", n);
            for (Point2 &q : p) q = t.invert(q).x;
            return arrayOf(p, n, u.ndim() == 3 ? std::size_t(u.shape(0)) : 0);
          },
          py::arg("u"), "the inverse-CDF map of uniform points u in [0, 1)^2")
      .def("__repr__", [](const Target &t) { return "nuld.Target('" + t.spec() + "')"; });
  // A SPEC string wherever a Target is expected.
  py::implicitly_convertible<py::str, Target>();

  m.def(
      "sequence",
      [](std::size_t n, const std::string &kind, const std::string &scramble, std::uint64_t seed,
         std::optional<std::size_t> instances, const TargetPtr &target) {
        if (n == 0) throw std::invalid_argument("sequence: n must be at least 1");
        SequenceOptions o{parseSequenceKind(kind), parseScramble(scramble), seed};
        PointSet set = generatePointSet(o, n, instances.value_or(1));
        if (target)
          for (Point2 &p : set.points) p = target->invert(p).x;
        return arrayOf(set.points, n, instances ? *instances : 0);
      },
      py::arg("n"), py::arg("kind") = "sobol", py::arg("scramble") = "owen", py::arg("seed") = 0,
      py::arg("instances") = py::none(), py::arg("target") = py::none(),
      R"(N points of a sequence (sobol, halton, random), scrambled (owen, shift, cp,
none); `instances` independent scramblings as (K, N, 2); mapped through
`target`'s inverse CDF when given.)");

  m.def(
      "optimize",
      [](const TargetPtr &target, std::size_t n, std::size_t instances,
         std::optional<std::string> preset, std::optional<py::function> progress,
         const py::kwargs &knobs) {
        const OptimizerSettings s = optimizerSettingsFor(*target, n, instances, preset, knobs);
        const DirectOptimizer opt(*target, s);
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
            const py::object answer = (*progress)(d);
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
      [](const DoubleArray &points, const std::string &metric, const TargetPtr &target, int grid) {
        std::size_t n;
        const std::vector<Point2> p = pointsOf(points, "discrepancy", n);
        const TargetPtr t = target ? target : targetOf("uniform");
        if (n == 0) throw std::invalid_argument("discrepancy: the set is empty");
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
        if (points.ndim() == 2) return py::object(py::float_(values[0]));
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
      [](const std::string &path) {
        const PointSet set = readPointSet(path);
        return py::make_tuple(arrayOf(set.points, set.n, set.instances()), set.metadata);
      },
      py::arg("path"), "(points (K, N, 2), metadata dict) of a point-set file (text or binary)");
  m.def(
      "write_points",
      [](const std::string &path, const DoubleArray &points,
         const std::map<std::string, std::string> &metadata) {
        PointSet set;
        set.points = pointsOf(points, "write_points", set.n);
        set.metadata = metadata;
        writePointSet(path, set);
      },
      py::arg("path"), py::arg("points"),
      py::arg("metadata") = std::map<std::string, std::string>{},
      "writes a point-set file (binary for .ptsb, else text), atomically");

  m.def(
      "generate_neural",
      [](const std::string &model, std::size_t instances, std::uint64_t seed,
         std::vector<double> gamma, std::optional<std::size_t> n) {
        const NeuralGenerator gen = NeuralGenerator::load(model);
        // The family checks gamma (and the generator the size) itself.
        const std::string spec = gen.family().target(gamma)->spec();
        PointSet set;
        {
          py::gil_scoped_release release;
          set = gen.generateSets(instances, seed, gamma, n.value_or(0));
        }
        return py::make_tuple(arrayOf(set.points, set.n, instances), spec);
      },
      py::arg("model"), py::arg("instances") = 1, py::arg("seed") = 0,
      py::arg("gamma") = std::vector<double>{}, py::arg("n") = py::none(),
      "(points (K, N, 2), target spec) of K sets a trained model (nuld train) generates");
}

}  // namespace nuld::python
