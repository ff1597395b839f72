#include "tools/python/args.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <new>
#include <stdexcept>

#include "sampler/enum_names.h"
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

py::array realArray(py::handle h, const Arg &a, const std::string &what) {
  if (h.is_none() || py::isinstance<py::str>(h) || py::isinstance<py::bytes>(h))
    a.typeError(what, h);
  const py::array arr = py::array::ensure(h);
  if (!arr) a.typeError(what, h);
  // Integers and floats only: numpy would cast a bool to 0 or 1 and drop a
  // complex number's imaginary part without a word.
  const char kind = arr.dtype().kind();
  if (kind != 'i' && kind != 'u' && kind != 'f') {
    if (!py::isinstance<py::array>(h)) a.typeError(what, h);
    throw py::type_error(a.function + ": " + a.name + ": expected " + what + " (got an array of " +
                         std::string(py::str(arr.dtype())) + ")");
  }
  return arr;
}

namespace {

DoubleArray pointArray(py::handle h, const Arg &a) {
  const DoubleArray arr =
      DoubleArray::ensure(realArray(h, a, kPointsShape + std::string(" of real numbers")));
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

Progress::Progress(py::handle h, const Arg &a) {
  if (h.is_none()) return;
  if (py::isinstance<py::bool_>(h)) {
    bar_ = h.cast<bool>();
    if (bar_) callback_ = py::module_::import("nuld.progress").attr("TextProgress")(a.function);
    return;
  }
  if (!PyCallable_Check(h.ptr())) a.typeError("None, True, False or a callable", h);
  callback_ = py::reinterpret_borrow<py::object>(h);
}

Progress::~Progress() {
  if (!bar_) return;
  try {
    callback_.attr("close")();  // ends the bar's line
  } catch (...) {
    // a failing bar does not hide the call's own result or error
  }
}

bool Progress::operator()(const py::dict &report) const {
  const py::object answer = callback_(report);
  return answer.is_none() || answer.cast<bool>();
}

std::vector<py::object> Signature::bind(const py::args &args, const py::kwargs &kwargs,
                                        py::dict *rest) const {
  const std::size_t most = std::min(positional, params.size());
  if (args.size() > most)
    throw py::type_error(function + ": takes " +
                         (most == 0 ? std::string("no positional arguments")
                                    : "at most " + std::to_string(most) + " positional argument" +
                                          (most == 1 ? "" : "s")) +
                         " (got " + std::to_string(args.size()) + ")");
  std::vector<py::object> v(params.size());
  for (std::size_t i = 0; i < args.size(); ++i) v[i] = args[i];
  for (const auto &[key, value] : kwargs) {
    const std::string k = py::str(key);
    const auto p =
        std::find_if(params.begin(), params.end(), [&](const Param &q) { return q.name == k; });
    if (p != params.end()) {
      py::object &slot = v[std::size_t(p - params.begin())];
      if (slot)
        throw py::type_error(function + ": argument '" + k +
                             "' given twice (by position and by keyword)");
      slot = py::reinterpret_borrow<py::object>(value);
    } else if (rest && std::find(settings.begin(), settings.end(), k) != settings.end()) {
      (*rest)[key] = value;
    } else {
      throw py::type_error(unknownKeyword(function, k, keywords()));
    }
  }
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i]) continue;
    if (!params[i].value)
      throw py::type_error(function + ": missing argument '" + params[i].name + "'");
    v[i] = params[i].value;
  }
  return v;
}

std::string Signature::docstring(const std::string &name, const std::string &doc,
                                 bool method) const {
  std::string s = name + "(" + (method ? "$self" : "");
  for (std::size_t i = 0; i < params.size(); ++i) {
    if (i > 0 || method) s += ", ";
    if (i == positional) s += "*, ";
    s += params[i].name;
    if (params[i].value) s += "=" + std::string(py::repr(params[i].value));
  }
  if (!settings.empty()) s += ", **settings";
  return s + ")\n--\n\n" + doc;
}

std::vector<std::string> Signature::keywords() const {
  std::vector<std::string> out;
  for (const Param &p : params) out.push_back(p.name);
  out.insert(out.end(), settings.begin(), settings.end());
  return out;
}

std::string unknownKeyword(const std::string &function, const std::string &word,
                           const std::vector<std::string> &keywords) {
  const std::string near = closestName(word, keywords);
  return function + ": unknown keyword '" + word + "'" +
         (near.empty() ? " (expected " + joinAlternatives(keywords) + ")"
                       : "; did you mean '" + near + "'?");
}

void detail::requireArity(const Signature &s, std::size_t arguments) {
  if (s.params.size() != arguments)
    throw std::logic_error(s.function + ": the signature names " + std::to_string(s.params.size()) +
                           " parameters, the binding takes " + std::to_string(arguments));
}

namespace {

// The C++ library's own words (std::bad_alloc, vector::_M_default_append,
// basic_string::substr, std::stoi's "stoi"), which say nothing to a Python
// user.
bool libraryText(const std::string &what) {
  for (const char *word : {"std::", "_M_", "bad_alloc", "bad_array_new_length",
                           "basic_string::", "__cxx", "vector::", "bitset::"})
    if (what.find(word) != std::string::npos) return true;
  for (const char *whole : {"stoi", "stol", "stoll", "stoul", "stoull", "stof", "stod", "stold"})
    if (what == whole) return true;
  return false;
}

std::string namedText(const std::string &function, const std::string &what) {
  return what.rfind(function + ":", 0) == 0 ? what : function + ": " + what;
}

// A Python exception of `type` (pybind11 has no class for some).
[[noreturn]] void raise(PyObject *type, const std::string &message) {
  PyErr_SetString(type, message.c_str());
  throw py::error_already_set();
}

[[noreturn]] void memoryError(const std::string &function) {
  raise(PyExc_MemoryError, function +
                               ": not enough memory for this call (fewer points, instances or "
                               "pixels would fit)");
}

}  // namespace

void rethrowNamed(const std::string &function) {
  const std::string generic = function + ": a value out of the range this call can handle";
  try {
    throw;
  } catch (py::error_already_set &) {
    throw;  // a Python exception: a callback's, or KeyboardInterrupt
  } catch (py::builtin_exception &) {
    throw;  // the module's own refusal (Arg), named already
  } catch (const std::bad_alloc &) {
    memoryError(function);
  } catch (const std::length_error &e) {
    if (libraryText(e.what())) memoryError(function);  // a container asked for too much
    throw py::value_error(namedText(function, e.what()));
  } catch (const std::filesystem::filesystem_error &e) {
    // The path first, as nuld's CLI says it (tools/nuld/main.cpp).
    raise(PyExc_RuntimeError, namedText(function, e.path1().string() + ": " + e.code().message()));
  } catch (const std::logic_error &e) {  // std::invalid_argument, std::out_of_range, ...
    throw py::value_error(libraryText(e.what()) ? generic : namedText(function, e.what()));
  } catch (const std::exception &e) {
    raise(PyExc_RuntimeError, libraryText(e.what()) ? function + ": failed in a library it uses"
                                                    : namedText(function, e.what()));
  }
}

void bindArgs(py::module_ &m) {
  // The same reading for the pure-Python engines (nuld/qmc.py).
  m.def("_count", [](py::object v, const std::string &f, const std::string &name, std::size_t lo) {
    return count(v, {f, name}, lo);
  });
  m.def("_flag", [](py::object v, const std::string &f, const std::string &name) {
    return flag(v, {f, name});
  });
  m.def("_seed", [](py::object v, const std::string &f, const std::string &name) {
    return seed(v, {f, name});
  });
  m.def("_points", [](py::object v, const std::string &f, const std::string &name) {
    std::size_t n, instances;
    const std::vector<Point2> p = points(v, {f, name}, n, &instances);
    return arrayOf(p, n, std::max<std::size_t>(instances, 1));
  });
  // A call of a Python function read as Signature::bind reads one: refused
  // in the module's words, else None.
  m.def("_check_call",
        [](const std::string &f, const std::vector<std::string> &names,
           const std::vector<bool> &required, std::size_t positional,
           const std::vector<std::string> &settings, py::tuple args, py::dict kwargs) {
          Signature s{f, {}, settings, positional};
          for (std::size_t i = 0; i < names.size(); ++i)
            s.params.push_back(required[i] ? Param(names[i]) : Param(names[i], py::none()));
          py::dict rest;
          s.bind(py::reinterpret_borrow<py::args>(args), py::reinterpret_borrow<py::kwargs>(kwargs),
                 &rest);
        });
}

}  // namespace nuld::python
