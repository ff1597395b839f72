#include "sampler/enum_names.h"

namespace nuld {

std::string joinAlternatives(const std::vector<std::string> &names) {
  std::string out;
  for (std::size_t k = 0; k < names.size(); ++k)
    out += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k];
  return out;
}

}  // namespace nuld
