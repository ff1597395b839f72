#pragma once
// Low-order moments of a point set against its target, for the graph
// generator's moment features and the trainer's moment term. A set whose
// points have the target's low-order moments integrates every quadratic
// exactly; the box discrepancy barely charges a set that drifts as a whole,
// smooth integrands see it in full (tools/experiments/graph_generator_log.md).
//   Square: x, y, x^2, x y, y^2 (about the centre).
//   Sphere: the direction w's components and their six products, w from the
//   equal-area map (a floor on sin theta keeps dw/dv finite at the poles).

#include <span>
#include <vector>

#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

struct MomentValues {
  int count = 0;  // 5 on the square, 9 on the sphere
  double value[9];
  Point2 gradient[9];  // d value / d x
};

// The moments at one point x of the domain's parameterization.
MomentValues momentsAt(Point2 x, Domain domain);

// The number of moments on a domain.
inline int momentCount(Domain domain) { return domain == Domain::Square ? 5 : 9; }

// The target's means of the moments: the cell masses of a grid x grid
// partition times the moments at the cell centres (a midpoint rule; at 256
// its error is far below any set's).
std::vector<double> targetMoments(const Target &target, Domain domain, int grid = 256);

// The set's mean moments minus the target's.
std::vector<double> momentErrors(std::span<const Point2> points, Domain domain,
                                 const std::vector<double> &targetMeans);

}  // namespace nuld
