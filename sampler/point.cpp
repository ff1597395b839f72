#include "sampler/point.h"

#include <stdexcept>

namespace nuld {

std::string toString(Domain d) {
  switch (d) {
    case Domain::Square: return "square";
    case Domain::Sphere: return "sphere";
    case Domain::Hemisphere: return "hemisphere";
  }
  return "?";
}

Domain parseDomain(const std::string &s) {
  if (s == "square") return Domain::Square;
  if (s == "sphere") return Domain::Sphere;
  if (s == "hemisphere") return Domain::Hemisphere;
  throw std::invalid_argument("unknown domain '" + s + "' (expected square, sphere or hemisphere)");
}

}  // namespace nuld
