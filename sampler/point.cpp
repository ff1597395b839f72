#include "sampler/point.h"

#include <algorithm>

namespace nuld {

Point2 wrapToDomain(Point2 p, Domain domain, double *vSign) {
  constexpr double kBelowOne = 0x1.fffffffffffffp-1;
  double sign = 1;
  if (domain != Domain::Square) {
    // Unfolded along a meridian, v is 2-periodic: past the south pole (v > 1)
    // the point is on the opposite meridian heading north; past the north
    // pole again it is back on its own meridian (two half turns).
    double v = p.y - 2 * std::floor(p.y / 2);
    if (v >= 2) v = 0;
    if (v > 1) {
      v = 2 - v;
      p.x += 0.5;
      sign = -1;
    }
    p.y = std::min(v, kBelowOne);
    p.x = wrapUnit(p.x);
  } else {
    p = {std::clamp(p.x, 0.0, kBelowOne), std::clamp(p.y, 0.0, kBelowOne)};
  }
  if (vSign) *vSign = sign;
  return p;
}

}  // namespace nuld
