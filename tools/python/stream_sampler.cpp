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

StreamSampler::StreamSampler(py::handle sampler, std::uint32_t domains, std::uint64_t seed)
    : domains_(domains), seedKey_(mix64(seed ^ 0x73747265616d00ull)), rest_(seed) {
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
    // Told the role when it takes a parameter named `domain`.
    try {
      const py::object parameters =
          py::module_::import("inspect").attr("signature")(sampler).attr("parameters");
      toldDomain_ = parameters.contains("domain");
    } catch (const py::error_already_set &) {  // no signature (a builtin): not told
      toldDomain_ = false;
    }
  } else {
    throw py::type_error(expected + " (got " + typeName(sampler) + ")");
  }
}

StreamSampler::~StreamSampler() {
  py::gil_scoped_acquire acquire;
  draw_ = py::object();
}

void StreamSampler::prepare(std::size_t spp, const SamplingTargets &targets) {
  if (targets.width == 0 || targets.domains == 0)
    throw BackendRefusal(name_ + ": deals its stream over an image; it serves renders only");
  spp_ = spp;
  integrator_ = targets.integrator;
  served_ = domains_ ? std::min(domains_, targets.domains) : targets.domains;
  std::vector<bool> served(targets.domains, false);
  std::fill(served.begin(), served.begin() + served_, true);
  rest_.prepare("the sampler", std::move(served), spp, targets);
  slot_.assign(std::size_t(targets.width) * targets.height, 0);
  staged_.assign(served_, {});
  const std::size_t tilePoints = kTilePixels * spp * std::max<std::uint32_t>(1, served_);
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
  for (std::uint32_t domain = 0; domain < served_; ++domain) {
    const SampleDomain d = SampleLayout::domain(domain);
    const std::size_t dims = toldDomain_ ? std::size_t(d.dimensions) : 2;
    std::string call = "render: sampler: " + call_ + "(" + std::to_string(n);
    py::object got;
    if (toldDomain_) {
      py::dict about;
      about["index"] = domain;
      about["role"] = toString(d.role);
      about["bounce"] = d.bounce;
      about["dimensions"] = d.dimensions;
      about["integrator"] = integrator_;
      call += ", domain={'index': " + std::to_string(domain) + ", 'role': '" + toString(d.role) +
              "', ...})";
      got = draw_(n, py::arg("domain") = about);
    } else {
      call += ")";
      got = draw_(n);
    }
    const std::string shapeWanted = "(n, " + std::to_string(dims) + ")";
    if (!py::isinstance<py::array>(got) && !PySequence_Check(got.ptr()))
      throw py::type_error(call + " returned " + typeName(got) + ", expected an " + shapeWanted +
                           " array");
    const DoubleArray a = DoubleArray::ensure(got);
    if (!a || a.ndim() != 2 || a.shape(0) != py::ssize_t(n) || a.shape(1) != py::ssize_t(dims)) {
      PyErr_Clear();
      std::string shape;
      if (a)
        for (py::ssize_t k = 0; k < a.ndim(); ++k)
          shape += (k ? ", " : "") + std::to_string(a.shape(k));
      throw py::value_error(call + " returned " + (a ? "shape (" + shape + ")" : typeName(got)) +
                            ", expected (" + std::to_string(n) + ", " + std::to_string(dims) +
                            ") real numbers");
    }
    std::vector<double> &numbers = staged_[domain];
    const std::size_t kept = std::size_t(d.dimensions);
    numbers.resize(n * kept);
    const double *v = a.data();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = 0; k < dims; ++k) {
        const double x = v[dims * i + k];
        if (!(x >= 0 && x < 1)) {
          std::string row;
          for (std::size_t j = 0; j < dims; ++j)
            row += (j ? ", " : "") + formatRoundTrip(v[dims * i + j]);
          throw py::value_error(call + " gave (" + row + ") at row " + std::to_string(i) +
                                ": expected numbers in [0, 1)");
        }
        if (k < kept) numbers[kept * i + k] = x;
      }
  }
}

std::uint64_t StreamSampler::shuffleSeed(std::uint64_t pixel, std::uint32_t domain) const {
  return mix64(mix64(seedKey_ + 0x9e3779b97f4a7c15ull * pixel) ^
               (0xd1b54a32d192ed03ull * (domain + 1)));
}

void StreamSampler::primary(std::uint64_t pixel, std::uint32_t domain,
                            std::span<Point2> out) const {
  if (!rest_.serves(domain)) return rest_.primary(pixel, domain, out);
  if (out.size() != spp_) throw std::logic_error("StreamSampler: asked for another spp");
  const double *set = staged_[domain].data() + 2 * std::size_t(slot_[pixel]) * spp_;
  for (std::size_t i = 0; i < spp_; ++i) out[i] = {set[2 * i], set[2 * i + 1]};
  shufflePoints(out, shuffleSeed(pixel, domain));
}

void StreamSampler::primary1D(std::uint64_t pixel, std::uint32_t domain,
                              std::span<double> out) const {
  if (!rest_.serves(domain)) return rest_.primary1D(pixel, domain, out);
  if (out.size() != spp_) throw std::logic_error("StreamSampler: asked for another spp");
  const double *set = staged_[domain].data() + std::size_t(slot_[pixel]) * spp_;
  std::copy(set, set + spp_, out.begin());
  shufflePoints(out, shuffleSeed(pixel, domain));
}

}  // namespace nuld::python
