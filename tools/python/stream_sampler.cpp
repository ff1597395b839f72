#include "tools/python/stream_sampler.h"

#include <pybind11/numpy.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "renderer/padding.h"
#include "sampler/io/round_trip.h"
#include "sampler/resources.h"
#include "sampler/sequences/rng.h"

namespace nuld::python {
namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// The points a batch stages: about 64 MiB, and at least one tile's.
constexpr std::size_t kStagePoints = std::size_t(1) << 22;
constexpr std::size_t kTilePixels = 16 * 16;

std::string typeName(py::handle h) { return py::str(py::type::of(h).attr("__name__")); }

}  // namespace

StreamSampler::StreamSampler(py::handle sampler, std::uint32_t pairs, std::uint64_t seed)
    : pairs_(pairs), seedKey_(mix64(seed ^ 0x73747265616d00ull)), rest_(seed) {
  const std::string expected =
      "render: sampler: expected a scipy.stats.qmc engine of d = 2 or a callable n -> (n, 2) "
      "array of points in [0, 1)^2";
  if (py::hasattr(sampler, "random") && py::hasattr(sampler, "d")) {
    const py::object d = sampler.attr("d");
    if (!py::isinstance<py::int_>(d) || d.cast<long long>() != 2)
      throw py::value_error(expected + " (got " + typeName(sampler) +
                            " with d = " + std::string(py::str(d)) + ")");
    draw_ = sampler.attr("random");
    name_ = "sampler:" + typeName(sampler);
    call_ = typeName(sampler) + ".random";
  } else if (PyCallable_Check(sampler.ptr())) {
    draw_ = py::reinterpret_borrow<py::object>(sampler);
    const std::string callable = py::hasattr(sampler, "__name__")
                                     ? std::string(py::str(sampler.attr("__name__")))
                                     : typeName(sampler);
    name_ = "sampler:" + callable;
    call_ = callable;
  } else {
    throw py::type_error(expected + " (got " + typeName(sampler) + ")");
  }
}

StreamSampler::~StreamSampler() {
  py::gil_scoped_acquire acquire;
  draw_ = py::object();
}

void StreamSampler::prepare(std::size_t spp, const SamplingTargets &targets) {
  if (targets.width == 0 || targets.pairs == 0)
    throw BackendRefusal(name_ + ": deals its stream over an image; it serves renders only");
  spp_ = spp;
  rest_.prepare("the sampler", pairs_ ? pairs_ : targets.pairs, spp, targets);
  const std::uint32_t served = rest_.served();
  slot_.assign(std::size_t(targets.width) * targets.height, 0);
  staged_.assign(served, {});
  const std::size_t tilePoints = kTilePixels * spp * std::max<std::uint32_t>(1, served);
  tilesPerStage_ = std::max<std::size_t>(1, kStagePoints / tilePoints);
  requireMemory(double(tilesPerStage_ * tilePoints) * sizeof(Point2),
                "render: sampler: a batch of " + std::to_string(tilesPerStage_) +
                    " tiles' points at " + std::to_string(spp) + " spp");
}

void StreamSampler::stage(std::span<const std::uint64_t> pixels) {
  for (std::size_t k = 0; k < pixels.size(); ++k) slot_[pixels[k]] = std::uint32_t(k);
  const std::size_t n = pixels.size() * spp_;
  py::gil_scoped_acquire acquire;
  // scipy's Sobol warns of every draw that is not a power of two. A pixel's
  // block is one when spp is, and starts at a multiple of it: each pixel's
  // set is a net all the same, so the warning is left out then.
  const py::object warnings = py::module_::import("warnings");
  const py::object quiet = warnings.attr("catch_warnings")();
  quiet.attr("__enter__")();
  if (std::has_single_bit(spp_))
    warnings.attr("filterwarnings")("ignore", "The balance properties");
  const struct Exit {
    py::object context;
    ~Exit() {
      try {
        context.attr("__exit__")(py::none(), py::none(), py::none());
      } catch (const py::error_already_set &) {  // restoring the filters cannot fail
      }
    }
  } exit{quiet};
  for (std::uint32_t pair = 0; pair < rest_.served(); ++pair) {
    const std::string call = "render: sampler: " + call_ + "(" + std::to_string(n) + ")";
    const py::object got = draw_(n);
    if (!py::isinstance<py::array>(got) && !PySequence_Check(got.ptr()))
      throw py::type_error(call + " returned " + typeName(got) + ", expected an (n, 2) array");
    const DoubleArray a = DoubleArray::ensure(got);
    if (!a || a.ndim() != 2 || a.shape(0) != py::ssize_t(n) || a.shape(1) != 2) {
      PyErr_Clear();
      std::string shape;
      if (a)
        for (py::ssize_t d = 0; d < a.ndim(); ++d)
          shape += (d ? ", " : "") + std::to_string(a.shape(d));
      throw py::value_error(call + " returned " + (a ? "shape (" + shape + ")" : typeName(got)) +
                            ", expected (" + std::to_string(n) + ", 2) real numbers");
    }
    std::vector<Point2> &points = staged_[pair];
    points.resize(n);
    const double *xy = a.data();
    for (std::size_t i = 0; i < n; ++i) {
      const Point2 p{xy[2 * i], xy[2 * i + 1]};
      if (!(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1))
        throw py::value_error(call + " gave the point (" + formatRoundTrip(p.x) + ", " +
                              formatRoundTrip(p.y) + ") at row " + std::to_string(i) +
                              ": expected points in [0, 1)^2");
      points[i] = p;
    }
  }
}

void StreamSampler::primary(std::uint64_t pixel, std::uint32_t pair, std::span<Point2> out) const {
  if (pair >= rest_.served()) return rest_.primary(pixel, pair, out);
  if (out.size() != spp_) throw std::logic_error("StreamSampler: asked for another spp");
  const Point2 *set = staged_[pair].data() + std::size_t(slot_[pixel]) * spp_;
  std::copy(set, set + spp_, out.begin());
  shufflePoints(out, mix64(mix64(seedKey_ + 0x9e3779b97f4a7c15ull * pixel) ^
                           (0xd1b54a32d192ed03ull * (pair + 1))));
}

}  // namespace nuld::python
