#include "scenes/json_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace nuld {
namespace {

std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

void JsonReader::fail(const std::string &expected) const {
  std::string got = value_.dump();
  if (got.size() > 60) got = got.substr(0, 57) + "...";
  refuse("expected " + expected + ", got " + got);
}

void JsonReader::refuse(const std::string &why) const {
  throw std::invalid_argument(file_ + ": field '" + (path_.empty() ? "(top level)" : path_) +
                              "': " + why);
}

bool JsonReader::has(const std::string &key) const {
  return value_.is_object() && value_.contains(key);
}

JsonReader JsonReader::operator[](const std::string &key) const {
  const std::string child = path_.empty() ? key : path_ + "." + key;
  if (!value_.is_object()) fail("an object with a field '" + key + "'");
  if (!value_.contains(key))
    throw std::invalid_argument(file_ + ": field '" + child + "' is missing");
  return JsonReader(value_.at(key), file_, child);
}

JsonReader JsonReader::at(std::size_t index) const {
  if (!value_.is_array() || index >= value_.size())
    fail("an array with an element " + std::to_string(index));
  return JsonReader(value_.at(index), file_, path_ + "[" + std::to_string(index) + "]");
}

std::size_t JsonReader::size() const {
  if (!value_.is_array()) fail("an array");
  return value_.size();
}

std::vector<std::string> JsonReader::keys() const {
  if (!value_.is_object()) fail("an object");
  std::vector<std::string> out;
  for (const auto &item : value_.items()) out.push_back(item.key());
  return out;
}

void JsonReader::allowOnly(const std::vector<std::string> &known) const {
  for (const std::string &k : keys())
    if (std::find(known.begin(), known.end(), k) == known.end()) {
      std::string list;
      for (const std::string &s : known) list += (list.empty() ? "" : ", ") + s;
      throw std::invalid_argument(file_ + ": unknown field '" +
                                  (path_.empty() ? k : path_ + "." + k) +
                                  "' (expected one of: " + list + ")");
    }
}

double JsonReader::number(double lo, double hi) const {
  const auto range = [&] {
    return "a number in [" + shortNumber(lo) + ", " + shortNumber(hi) + "]";
  };
  if (!value_.is_number()) fail(lo <= -1e300 && hi >= 1e300 ? "a number" : range());
  const double v = value_.get<double>();
  if (!std::isfinite(v) || v < lo || v > hi) fail(range());
  return v;
}

int JsonReader::integer(int lo, int hi) const {
  const std::string expected =
      "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (!value_.is_number_integer()) fail(expected);
  const long long v = value_.get<long long>();
  if (v < lo || v > hi) fail(expected);
  return int(v);
}

bool JsonReader::boolean() const {
  if (!value_.is_boolean()) fail("true or false");
  return value_.get<bool>();
}

std::string JsonReader::string() const {
  if (!value_.is_string()) fail("a string");
  return value_.get<std::string>();
}

Vec3 JsonReader::vec3() const {
  if (!value_.is_array() || value_.size() != 3) fail("an array of 3 numbers");
  return {at(0).number(), at(1).number(), at(2).number()};
}

Rgb JsonReader::reflectance() const {
  if (value_.is_number()) return Rgb::grey(number(0, 1));
  if (!value_.is_array() || value_.size() != 3) fail("[r, g, b] or one number, each in [0, 1]");
  return {at(0).number(0, 1), at(1).number(0, 1), at(2).number(0, 1)};
}

Rgb JsonReader::radiance() const {
  constexpr double kMax = 1e30;  // finite, and its square too
  if (value_.is_number()) return Rgb::grey(number(0, kMax));
  if (!value_.is_array() || value_.size() != 3)
    fail("[r, g, b] or one number, each finite and >= 0");
  return {at(0).number(0, kMax), at(1).number(0, kMax), at(2).number(0, kMax)};
}

std::vector<std::string> JsonReader::strings() const {
  if (value_.is_string()) return {value_.get<std::string>()};
  std::vector<std::string> out;
  for (std::size_t i = 0; i < size(); ++i) out.push_back(at(i).string());
  return out;
}

double JsonReader::number(const std::string &key, double fallback, double lo, double hi) const {
  return has(key) ? (*this)[key].number(lo, hi) : fallback;
}

std::string JsonReader::string(const std::string &key, const std::string &fallback) const {
  return has(key) ? (*this)[key].string() : fallback;
}

}  // namespace nuld
