#pragma once
// Typed reads from a parsed JSON document that report bad input as
// "FILE: field 'camera.fov': expected a number in (0, 180), got "wide"".
// nlohmann::json stays inside the scenes module's .cpp files.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "materials/rgb.h"
#include "materials/vec3.h"
#include "sampler/enum_names.h"

namespace nuld {

class JsonReader {
 public:
  JsonReader(const nlohmann::json &value, std::string file, std::string path = "")
      : value_(value), file_(std::move(file)), path_(std::move(path)) {}

  bool has(const std::string &key) const;
  JsonReader operator[](const std::string &key) const;  // the field must exist
  JsonReader at(std::size_t index) const;
  std::size_t size() const;               // of an array (error otherwise)
  std::vector<std::string> keys() const;  // of an object (error otherwise)
  // Every key must be one of `known` (catches typos such as "rougness").
  void allowOnly(const std::vector<std::string> &known) const;

  double number(double lo = -1e300, double hi = 1e300) const;
  int integer(int lo, int hi) const;
  bool boolean() const;
  std::string string() const;
  Vec3 vec3() const;
  Rgb reflectance() const;                   // [r, g, b] or one grey number, each in [0, 1]
  Rgb radiance() const;                      // [r, g, b] or one grey number, each finite, >= 0
  std::vector<std::string> strings() const;  // a string or an array of strings
  // A string that names a value of `names`; fails listing the names and,
  // after them, `note`.
  template <class E, std::size_t N>
  E oneOf(const EnumTable<E, N> &names, const std::string &note = "") const {
    if (const auto v = names.find(string())) return *v;
    fail(names.expected() + note);
  }

  double number(const std::string &key, double fallback, double lo = -1e300,
                double hi = 1e300) const;
  std::string string(const std::string &key, const std::string &fallback) const;

  [[noreturn]] void fail(const std::string &expected) const;
  // "FILE: field 'PATH': WHY", for a value that reads well but cannot be used.
  [[noreturn]] void refuse(const std::string &why) const;
  const std::string &file() const { return file_; }
  const std::string &path() const { return path_; }

 private:
  const nlohmann::json &value_;
  std::string file_, path_;
};

}  // namespace nuld
