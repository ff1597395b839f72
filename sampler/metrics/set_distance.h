#pragma once
// How different the instances of a point-set file are: the mean, over pairs
// of instances, of the symmetric mean nearest-neighbour (chamfer) distance,
// measured in the unit-square parameterization. Zero means identical sets; a
// generator that ignores its random offset (mode collapse) scores near zero,
// while independently randomized sets of N points score about the spacing
// of a set, ~0.5 / sqrt(N).

#include "sampler/point.h"

namespace nuld {

// Requires at least two instances; exact, O(K^2 N^2).
double meanSetDistance(const PointSet &set);

}  // namespace nuld
