#pragma once
// The module's own reading of Python arguments (tools/python/README.md,
// "Bad input"): every public function takes its arguments as Python objects
// and reads them here, so a wrong type, a negative or fractional count or a
// None where a value is needed is refused in one wording,
// "FUNCTION: ARGUMENT: expected WHAT (got VALUE)", a TypeError for a wrong
// type and a ValueError for a wrong value, never pybind11's signature dump.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tools/python/bindings.h"

namespace nuld::python {

// Where an argument is read: the public function's name and the argument's.
struct Arg {
  std::string function, name;
  [[noreturn]] void typeError(const std::string &expected, py::handle got) const;
  [[noreturn]] void valueError(const std::string &expected, py::handle got) const;
};

// A whole number (an int or numpy integer, not a bool, not a float) in
// [lo, hi].
std::int64_t wholeNumber(py::handle h, const Arg &a, std::int64_t lo = 0,
                         std::int64_t hi = INT64_MAX);
std::size_t count(py::handle h, const Arg &a, std::size_t lo = 0);
std::uint64_t seed(py::handle h, const Arg &a);           // any whole number in [0, 2^64)
double number(py::handle h, const Arg &a);                // an int or a float, finite
std::string text(py::handle h, const Arg &a);             // a str
std::vector<double> numbers(py::handle h, const Arg &a);  // a sequence of numbers
bool flag(py::handle h, const Arg &a);                    // True or False

// None, or what `read` makes of the value.
template <class F>
auto optional(py::handle h, const Arg &a, F read) -> std::optional<decltype(read(h, a))> {
  if (h.is_none()) return std::nullopt;
  return read(h, a);
}

// Points (N, 2) or (K, N, 2) as the point-set readers check them
// (pointProblem: finite, in the unit square); `n` receives N and
// `instances` K (0 for an (N, 2) set).
std::vector<Point2> points(py::handle h, const Arg &a, std::size_t &n,
                           std::size_t *instances = nullptr);

// _count, _flag and _points: the same reading for nuld/qmc.py.
void bindArgs(py::module_ &m);

}  // namespace nuld::python
