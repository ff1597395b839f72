#pragma once
// An orthonormal shading frame. Materials work in the local frame where the
// normal is +z and the tangent +x (the supplement's convention).

#include <cmath>

#include "materials/vec3.h"

namespace nuld {

struct Frame {
  Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

  // Any tangent (Duff et al. 2017's branchless basis: no singularity at n.z = -1).
  static Frame fromNormal(Vec3 n) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1 / (sign + n.z), b = n.x * n.y * a;
    return {{1 + sign * n.x * n.x * a, sign * b, -sign * n.x}, {b, sign + n.y * n.y * a, -n.y}, n};
  }

  Vec3 toLocal(Vec3 v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
  Vec3 toWorld(Vec3 v) const { return v.x * s + v.y * t + v.z * n; }
};

}  // namespace nuld
