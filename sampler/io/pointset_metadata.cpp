#include "sampler/io/pointset_metadata.h"

namespace nuld {

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

}  // namespace nuld
