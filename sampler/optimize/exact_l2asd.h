#pragma once
// The exact L2asd objective for a uniform target: the closed form of
// DESIGN.md §3 and its gradient, O(N^2) per evaluation, no sampled boxes and
// no sigmoid. It is the expectation of the hard multiple-corner box loss, so
// it optimizes the same quantity as Algorithm 1 without its noise.

#include <span>

#include "sampler/point.h"

namespace nuld {

// Returns L2asd^2 of the points and writes its gradient (unless empty).
// Deterministic: each point's gradient is one ordered sum.
double l2asdSquaredWithGradient(std::span<const Point2> points, std::span<Point2> grad = {});

}  // namespace nuld
