#include "tools/python/args.h"

#include <climits>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "sampler/io/pointset_io.h"

namespace nuld::python {

namespace {

// The value as the message quotes it: its repr, shortened, and for a type
// error its type.
std::string shown(py::handle h, bool withType) {
  std::string r = py::str(py::repr(h));
  if (r.size() > 40) r = r.substr(0, 37) + "...";
  if (withType && !h.is_none()) {
    const std::string type = py::str(h.get_type().attr("__name__"));
    r += (std::string("aeiou").find(type[0]) != std::string::npos ? ", an " : ", a ") + type;
  }
  return r;
}

bool isWhole(py::handle h) { return !py::isinstance<py::bool_>(h) && PyIndex_Check(h.ptr()); }

constexpr const char *kPointsShape = "an array of shape (N, 2) or (K, N, 2)";

}  // namespace

void Arg::typeError(const std::string &expected, py::handle got) const {
  throw py::type_error(function + ": " + name + ": expected " + expected + " (got " +
                       shown(got, true) + ")");
}

void Arg::valueError(const std::string &expected, py::handle got) const {
  throw py::value_error(function + ": " + name + ": expected " + expected + " (got " +
                        shown(got, false) + ")");
}

std::int64_t wholeNumber(py::handle h, const Arg &a, std::int64_t lo, std::int64_t hi) {
  // The bounds a caller checks itself (lo at INT_MIN) or that are no real
  // limit (hi at INT_MAX) are not spelled out.
  const std::string expected =
      "a whole number" + (lo <= INT_MIN ? std::string()
                          : hi >= INT_MAX
                              ? " >= " + std::to_string(lo)
                              : " from " + std::to_string(lo) + " to " + std::to_string(hi));
  if (!isWhole(h)) a.typeError(expected, h);
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(
      py::int_(py::reinterpret_borrow<py::object>(h)).ptr(), &overflow);
  if (overflow != 0 || v < lo || v > hi) a.valueError(expected, h);
  return v;
}

std::size_t count(py::handle h, const Arg &a, std::size_t lo) {
  return std::size_t(wholeNumber(h, a, std::int64_t(lo)));
}

std::uint64_t seed(py::handle h, const Arg &a) {
  const std::string expected = "a whole number from 0 to 2^64 - 1";
  if (!isWhole(h)) a.typeError(expected, h);
  const py::int_ v(py::reinterpret_borrow<py::object>(h));
  if (PyObject_RichCompareBool(v.ptr(), py::int_(0).ptr(), Py_LT) == 1) a.valueError(expected, h);
  const unsigned long long u = PyLong_AsUnsignedLongLong(v.ptr());
  if (PyErr_Occurred()) {
    PyErr_Clear();
    a.valueError(expected, h);
  }
  return u;
}

double number(py::handle h, const Arg &a) {
  if (py::isinstance<py::bool_>(h) ||
      !(PyFloat_Check(h.ptr()) || PyIndex_Check(h.ptr()) ||
        py::isinstance(h, py::module_::import("numpy").attr("floating"))))
    a.typeError("a number", h);
  const double v = py::float_(py::reinterpret_borrow<py::object>(h));
  if (!std::isfinite(v)) a.valueError("a finite number", h);
  return v;
}

std::string text(py::handle h, const Arg &a) {
  if (!py::isinstance<py::str>(h)) a.typeError("a str", h);
  return h.cast<std::string>();
}

std::vector<double> numbers(py::handle h, const Arg &a) {
  const std::string expected = "a sequence of numbers";
  if (py::isinstance<py::str>(h) || !PySequence_Check(h.ptr())) {
    if (!py::isinstance(h, py::module_::import("numpy").attr("ndarray"))) a.typeError(expected, h);
  }
  std::vector<double> out;
  for (py::handle item : py::iter(h))
    out.push_back(number(item, Arg{a.function, a.name + " item"}));
  return out;
}

namespace {

DoubleArray pointArray(py::handle h, const Arg &a) {
  if (h.is_none() || py::isinstance<py::str>(h))
    a.typeError(kPointsShape + std::string(" of numbers"), h);
  DoubleArray arr = DoubleArray::ensure(h);
  if (!arr) a.typeError(kPointsShape + std::string(" of numbers"), h);
  if (!((arr.ndim() == 2 && arr.shape(1) == 2) || (arr.ndim() == 3 && arr.shape(2) == 2)) ||
      arr.size() == 0) {
    std::string shape;
    for (py::ssize_t d = 0; d < arr.ndim(); ++d)
      shape += (d ? ", " : "") + std::to_string(arr.shape(d));
    throw py::value_error(a.function + ": " + a.name + ": expected " + kPointsShape +
                          " with N and K >= 1, got (" + shape + ")");
  }
  return arr;
}

}  // namespace

std::vector<Point2> points(py::handle h, const Arg &a, std::size_t &n, std::size_t *instances) {
  static_assert(sizeof(Point2) == 2 * sizeof(double));
  const DoubleArray arr = pointArray(h, a);
  const bool bank = arr.ndim() == 3;
  n = std::size_t(arr.shape(bank ? 1 : 0));
  if (instances) *instances = bank ? std::size_t(arr.shape(0)) : 0;
  std::vector<Point2> out(std::size_t(arr.size()) / 2);
  if (!out.empty())
    std::memcpy(static_cast<void *>(out.data()), arr.data(), out.size() * sizeof(Point2));
  for (std::size_t i = 0; i < out.size(); ++i)
    if (const std::string why = pointProblem(out[i]); !why.empty())
      throw py::value_error(
          a.function + ": " + a.name + "[" +
          (bank ? std::to_string(i / n) + ", " + std::to_string(i % n) : std::to_string(i)) +
          "]: " + why);
  return out;
}

bool flag(py::handle h, const Arg &a) {
  if (!py::isinstance<py::bool_>(h) &&
      !py::isinstance(h, py::module_::import("numpy").attr("bool_")))
    a.typeError("True or False", h);
  return py::cast<bool>(py::bool_(py::reinterpret_borrow<py::object>(h)));
}

void bindArgs(py::module_ &m) {
  // The same reading for the pure-Python engines (nuld/qmc.py).
  m.def("_count", [](py::object v, const std::string &f, const std::string &name, std::size_t lo) {
    return count(v, {f, name}, lo);
  });
  m.def("_flag", [](py::object v, const std::string &f, const std::string &name) {
    return flag(v, {f, name});
  });
  m.def("_points", [](py::object v, const std::string &f, const std::string &name) {
    std::size_t n, instances;
    const std::vector<Point2> p = points(v, {f, name}, n, &instances);
    return arrayOf(p, n, std::max<std::size_t>(instances, 1));
  });
}

}  // namespace nuld::python
