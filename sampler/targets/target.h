#pragma once
// A target is a probability density on a 2D domain, parameterized over the
// unit square (the sphere through the cylindrical equal-area map, so a
// density on the square is a density per solid angle up to the factor 4 pi).
//
// Every target gives its density, the exact mass of any axis-aligned box, and
// usually an inverse-CDF map (the Rosenblatt transform: marginal, then
// conditional) that turns uniform points into points distributed by the
// target. The map's full 2x2 Jacobian is returned because density-mapped
// optimization back-propagates through it.

#include <memory>
#include <string>

#include "sampler/io/content_hash.h"
#include "sampler/point.h"

namespace nuld {

// J[r][c] = d x_r / d u_c.
struct Jacobian2 {
  double m[2][2] = {{1, 0}, {0, 1}};
  double determinant() const { return m[0][0] * m[1][1] - m[0][1] * m[1][0]; }
  // J^T g: pulls a gradient with respect to x back to one with respect to u.
  Point2 transposeTimes(Point2 g) const {
    return {m[0][0] * g.x + m[1][0] * g.y, m[0][1] * g.x + m[1][1] * g.y};
  }
};

struct Inversion {
  Point2 x;
  Jacobian2 jacobian;
};

class Target {
 public:
  virtual ~Target() = default;

  // The SPEC string that rebuilds this target (see makeTarget).
  virtual std::string spec() const = 0;
  // What the density is, as a stable hash (sampler/io/content_hash.h): two
  // targets with the same hash have the same density, wherever their data
  // came from (the same map under another path or asset root). By default
  // the spec's; targets made from data hash the data.
  virtual std::string contentHash() const { return ContentHash().add("spec:").add(spec()).hex(); }
  virtual Domain domain() const { return Domain::Square; }
  virtual bool isUniform() const { return false; }

  // Density with respect to area on the unit square; integrates to 1.
  virtual double pdf(Point2 p) const = 0;

  // Exact probability of the box intersected with the unit square.
  virtual double mass(const Box2 &box) const = 0;

  virtual bool hasInverse() const { return true; }
  // u in [0,1)^2 -> x distributed by the target, with dx/du.
  virtual Inversion invert(Point2 u) const = 0;
};

}  // namespace nuld
