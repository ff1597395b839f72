#include "sampler/enum_names.h"

#include <algorithm>

namespace nuld {

std::string joinAlternatives(const std::vector<std::string> &names) {
  std::string out;
  for (std::size_t k = 0; k < names.size(); ++k)
    out += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k];
  return out;
}

std::string closestName(const std::string &word, const std::vector<std::string> &names) {
  // Levenshtein distance, one row at a time.
  const auto distance = [](const std::string &a, const std::string &b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j) {
        const std::size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
        diagonal = up;
      }
    }
    return row[b.size()];
  };
  std::string best;
  std::size_t bestDistance = word.size() / 3 + 1;
  for (const std::string &n : names)
    if (const std::size_t d = distance(word, n); d < bestDistance) best = n, bestDistance = d;
  return best;
}

std::string didYouMean(const std::string &word, const std::vector<std::string> &names) {
  const std::string near = closestName(word, names);
  return near.empty() ? "" : " (did you mean '" + near + "'?)";
}

}  // namespace nuld
