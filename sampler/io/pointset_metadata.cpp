#include "sampler/io/pointset_metadata.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace nuld {
namespace {

[[noreturn]] void bad(const std::string &file, std::string_view key, const std::string &what) {
  throw std::runtime_error(file + ": point-set metadata '" + std::string(key) + "' " + what);
}

}  // namespace

void setMeta(PointSet &set, std::string_view key, std::string value) {
  set.metadata[std::string(key)] = std::move(value);
}

const std::string *findMeta(const PointSet &set, std::string_view key) {
  const auto it = set.metadata.find(std::string(key));
  return it == set.metadata.end() ? nullptr : &it->second;
}

std::string metaOr(const PointSet &set, std::string_view key, std::string_view fallback) {
  const std::string *value = findMeta(set, key);
  return value ? *value : std::string(fallback);
}

const std::string &metaString(const PointSet &set, std::string_view key, const std::string &file) {
  const std::string *value = findMeta(set, key);
  if (!value) bad(file, key, "is missing");
  return *value;
}

double metaNumber(const PointSet &set, std::string_view key, const std::string &file) {
  const std::string &v = metaString(set, key, file);
  double x = 0;
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
  if (v.empty() || ec != std::errc() || end != v.data() + v.size() || !std::isfinite(x))
    bad(file, key, "is not a number: '" + v + "'");
  return x;
}

std::size_t metaSize(const PointSet &set, std::string_view key, const std::string &file) {
  const std::string &v = metaString(set, key, file);
  std::size_t x = 0;
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
  if (v.empty() || ec != std::errc() || end != v.data() + v.size())
    bad(file, key, "is not a count: '" + v + "'");
  return x;
}

}  // namespace nuld
