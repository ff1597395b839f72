#pragma once
// The module's own reading of Python arguments (tools/python/README.md,
// "Bad input"): every public function takes its arguments as Python objects
// and reads them here, so a wrong type, a negative or fractional count or a
// None where a value is needed is refused in one wording,
// "FUNCTION: ARGUMENT: expected WHAT (got VALUE)", a TypeError for a wrong
// type and a ValueError for a wrong value, never pybind11's signature dump.
// The call itself is read here too (Signature): an unknown keyword is a
// TypeError naming the closest keyword, and what the library underneath
// throws reaches Python named by the function, never in C++'s words.

#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
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

// `h` as a numpy array of real numbers (integer or floating dtype; a bool,
// complex, str or object array is a TypeError expecting `what`).
py::array realArray(py::handle h, const Arg &a, const std::string &what);

// Points (N, 2) or (K, N, 2) as the point-set readers check them
// (pointProblem: finite, in the unit square); `n` receives N and
// `instances` K (0 for an (N, 2) set).
std::vector<Point2> points(py::handle h, const Arg &a, std::size_t &n,
                           std::size_t *instances = nullptr);

// progress: None or False (none), True (nuld.progress.TextProgress, a text
// bar on stderr, named by the function and closed with this object) or a
// callable taking a dict. Call it with the GIL held; it answers false when
// the callable returned False (stop).
class Progress {
 public:
  Progress(py::handle h, const Arg &a);
  ~Progress();
  Progress(const Progress &) = delete;
  Progress &operator=(const Progress &) = delete;
  explicit operator bool() const { return bool(callback_); }
  bool operator()(const py::dict &report) const;

 private:
  py::object callback_;
  bool bar_ = false;
};

// One parameter of a public function: its name and default (none given: the
// argument is required).
struct Param {
  std::string name;
  py::object value;  // a null object: required
  explicit Param(std::string n) : name(std::move(n)) {}
  template <class T>
  Param(std::string n, T v) : name(std::move(n)) {
    if constexpr (std::is_base_of_v<py::handle, T>)
      value = py::reinterpret_borrow<py::object>(v);
    else
      value = py::cast(std::move(v));
  }
};

// A public function's parameters, in order. bind() reads a call as Python
// would, but refuses in the module's words (a TypeError): an unknown keyword
// ("FUNCTION: unknown keyword 'resolutoin'; did you mean 'resolution'?"),
// too many positional arguments, an argument given twice or a required one
// missing. Keywords named in `settings` (optimize's) are taken beyond the
// parameters and come back in `rest`.
struct Signature {
  std::string function;
  std::vector<Param> params;
  std::vector<std::string> settings{};
  std::size_t positional = SIZE_MAX;  // how many may be given by position

  std::vector<py::object> bind(const py::args &args, const py::kwargs &kwargs,
                               py::dict *rest = nullptr) const;
  // The docstring: the signature as Python's help and inspect read it
  // ("NAME(a, b='x')\n--\n\n"), then `doc`.
  std::string docstring(const std::string &name, const std::string &doc, bool method) const;
  // Every keyword the function takes.
  std::vector<std::string> keywords() const;
};

// "FUNCTION: unknown keyword 'WORD'; did you mean 'NAME'?" (or the keywords
// it takes, when none is close).
std::string unknownKeyword(const std::string &function, const std::string &word,
                           const std::vector<std::string> &keywords);

// Runs `body`, turning what the library throws into Python's exceptions named
// by `function` (std::invalid_argument a ValueError, std::runtime_error a
// RuntimeError, an allocation failure a MemoryError), with any C++ library
// text (std::..., bad_alloc, vector::_M_...) replaced by the module's words.
[[noreturn]] void rethrowNamed(const std::string &function);
template <class F>
auto named(const std::string &function, F &&body) -> decltype(body()) {
  try {
    return body();
  } catch (...) {
    rethrowNamed(function);
  }
}

namespace detail {
template <class T>
struct Call : Call<decltype(&T::operator())> {};
template <class C, class R, class... A>
struct Call<R (C::*)(A...) const> {
  static constexpr std::size_t arity = sizeof...(A);
  // Whether the last argument takes the settings given (a py::dict).
  static constexpr bool rest = (std::is_same_v<std::decay_t<A>, py::dict> || ...);
};

// A binding whose lambda takes another number of arguments than its
// signature names fails at import (std::logic_error), not at a call.
void requireArity(const Signature &s, std::size_t arguments);

// f(lead..., values[0], ..., values[N - 1][, rest]) as a Python object.
template <std::size_t N, bool Rest, class F, class... Lead>
py::object invoke(F &f, const std::vector<py::object> &v, const py::dict &rest, Lead &...lead) {
  return [&]<std::size_t... I>(std::index_sequence<I...>) {
    const auto call = [&] {
      if constexpr (Rest)
        return f(lead..., v[I]..., rest);
      else
        return f(lead..., v[I]...);
    };
    using R = decltype(call());
    if constexpr (std::is_void_v<R>) {
      call();
      return py::object(py::none());
    } else if constexpr (std::is_base_of_v<py::handle, R>) {
      return py::object(call());
    } else {
      return py::object(py::cast(call()));
    }
  }
  (std::make_index_sequence<N>{});
}
}  // namespace detail

// m.NAME, reading its call through `s`: `f` takes one py::object per
// parameter (and, with s.settings, a py::dict of the settings given).
template <class F>
void defFunction(py::module_ &m, const char *name, Signature s, F f, const std::string &doc) {
  using C = detail::Call<F>;
  detail::requireArity(s, C::arity - C::rest);
  const std::string docstring = s.docstring(name, doc, false);
  m.def(
      name,
      [s = std::move(s), f = std::move(f)](py::args args, py::kwargs kwargs) mutable {
        return named(s.function, [&] {
          py::dict rest;
          const std::vector<py::object> v = s.bind(args, kwargs, &rest);
          return detail::invoke<C::arity - C::rest, C::rest>(f, v, rest);
        });
      },
      docstring.c_str());
}

// cls.NAME, reading its call through `s`: `f` takes the object, then one
// py::object per parameter.
template <class Class, class F>
void defMethod(Class &cls, const char *name, Signature s, F f, const std::string &doc) {
  using Self = typename Class::type;
  using C = detail::Call<F>;
  detail::requireArity(s, C::arity - 1);
  const std::string docstring = s.docstring(name, doc, true);
  cls.def(
      name,
      [s = std::move(s), f = std::move(f)](const Self &self, py::args args,
                                           py::kwargs kwargs) mutable {
        return named(s.function, [&] {
          const std::vector<py::object> v = s.bind(args, kwargs);
          return detail::invoke<C::arity - 1, false>(f, v, py::dict(), self);
        });
      },
      docstring.c_str());
}

// _count, _flag, _seed, _points and _check_call: the same reading for
// nuld/qmc.py.
void bindArgs(py::module_ &m);

}  // namespace nuld::python
