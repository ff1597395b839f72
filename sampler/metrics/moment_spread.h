#pragma once
// How much a point-set file's instances move as a whole: over the
// instances, the standard deviation of each set's mean of x, of y and of
// x y (unit-square parameterization). A set's mean error is what a smooth
// integrand sees and what a box discrepancy barely charges, so sets that
// drift together (a learned generator's stages moving every point the same
// way) integrate smooth functions badly at a good discrepancy. Owen-
// scrambled Sobol sets of N points spread by about N^(-3/2) (a stratified
// mean), independent uniform points by sqrt(1/(12 N)) in x and y.

#include "sampler/point.h"

namespace nuld {

struct MomentSpread {
  double x = 0, y = 0, xy = 0;
};

// Requires at least two instances.
MomentSpread momentSpread(const PointSet &set);

}  // namespace nuld
